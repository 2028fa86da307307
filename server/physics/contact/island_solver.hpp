// The contact laws at every point of a group of bodies in contact (an island: bodies touching each
// other, and static parts), solved together: the many-body counterpart of point_solver.hpp.
//
// Row i joins body a (and body b, or a static part) at a point, r_a and r_b its offsets from each
// centre of mass, n its normal from b to a. The rows' impulses P change the bodies' velocities,
// and the point's relative velocity u = (v_a + w_a x r_a) - (v_b + w_b x r_b) by
//   K = K_a(r_a, r_a) + K_b(r_b, r_b)   (point_solver.hpp's K for each body)
// for its own impulse. The laws: n . u >= target with P_n >= 0 and complementarity; Coulomb
// friction, |P_t| <= mu P_n, sticking (no tangential u) where the disk allows. Projected
// Gauss-Seidel over the rows (sequential impulses, Catto, GDC 2005), from the impulses the rows
// carry in (warm start: last step's), until every law holds to rel_tol of the speeds involved or
// max_iterations.
#pragma once

#include <span>

#include "physics/contact/point_solver.hpp"
#include "physics/math.hpp"

namespace rigid::physics::contact {

struct IslandBody {
  Response resp;
  Vec3 v = Vec3::Zero();  // the velocities being solved for (updated in place)
  Vec3 w = Vec3::Zero();
};

struct IslandRow {
  int a = -1, b = -1;  // bodies of the island; b = -1: a static part
  Vec3 r_a = Vec3::Zero(), r_b = Vec3::Zero();
  Vec3 n = Vec3::UnitZ();
  double mu = 0.0;
  double target = 0.0;
  // In: the impulses to start from (warm start); out: the impulses solved.
  double pn = 0.0;
  Eigen::Vector2d pt = Eigen::Vector2d::Zero();
  // The solve's own: the tangents, the normal response, the tangential 2x2 inverse.
  Vec3 t1 = Vec3::Zero(), t2 = Vec3::Zero();
  double k_n = 0.0;
  Eigen::Matrix2d Ktt_inv = Eigen::Matrix2d::Zero();
  bool sticks = false;
};

struct IslandResult {
  int iterations = 0;
  bool converged = false;
};

IslandResult solve_island(std::span<IslandBody> bodies, std::span<IslandRow> rows,
                          int max_iterations, double rel_tol);

}  // namespace rigid::physics::contact
