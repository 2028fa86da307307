// The impulses (or forces) at a body's contact points that satisfy the contact laws at once, for
// every point together: so that a box landing flat on four corners gets four impulses that leave
// it without spin, and a box resting on four corners four forces that hold it.
//
// A point i at r_i from the centre of mass, with unit normal n_i (from the part to the body),
// changes its velocity by u_i += sum_j K_ij P_j under impulses P_j, with the course notes' matrix
//   K_ij = M^-1 - [r_i]x I_W^-1 [r_j]x
// (M^-1 per world axis: frozen translation has none; I_W^-1 the world-frame inverse inertia, with
// the rotation constraints of the body). The same relation holds between forces and accelerations.
// The laws, per point:
//   normal:   n_i . u_i >= target_i, P_n >= 0, and P_n > 0 only where n_i . u_i == target_i
//             (an impact: target = -e times the approach speed; a force: target = 0);
//   friction: sliding, P_t = -mu P_n s_i along the point's slip direction s_i; sticking, no
//             tangential motion with |P_t| <= mu P_n.
// Points on one face of a part (a patch: the same `patch` and normal) stick together: their
// friction is one force at the patch's centre of pressure and one moment about its normal (as
// Box2D's and Jolt's manifolds take it), bounded by mu N and by mu N times the points' mean
// distance from that centre. Friction per point would leave the split between redundant points
// free, and an iterative solve can wind it into opposing pairs that use up the friction a face
// has (a block on an incline then slides below its friction angle).
// Solved by projected block Gauss-Seidel iterated until every law holds to round-off (Moreau,
// Jean; exact here because it runs to convergence, not to a budget).
#pragma once

#include <algorithm>
#include <array>

#include "physics/math.hpp"

namespace rigid::physics::contact {

// How a body answers an impulse: per world axis 1/m (0 on frozen axes), and I_W^-1.
struct Response {
  Vec3 inv_m = Vec3::Zero();
  Mat3 inv_I_W = Mat3::Zero();
  // The change of (v, w) under an impulse P at r.
  Vec3 dv(const Vec3& P) const { return inv_m.cwiseProduct(P); }
  Vec3 dw(const Vec3& r, const Vec3& P) const { return inv_I_W * r.cross(P); }
  // K for a point at r_i answering an impulse at r_j.
  Mat3 K(const Vec3& r_i, const Vec3& r_j) const {
    return Mat3(inv_m.asDiagonal()) - skew(r_i) * inv_I_W * skew(r_j);
  }
};

struct PointRow {
  Vec3 r_W = Vec3::Zero();  // from the centre of mass
  Vec3 n_W = Vec3::UnitZ();
  double mu = 0.0;
  double target = 0.0;  // lower bound of n . u after the solve
  bool sliding = false;
  Vec3 slip_W = Vec3::Zero();  // unit tangential slip direction when sliding
  Vec3 u_W = Vec3::Zero();     // the point's velocity (or acceleration) before the solve
  int patch = -1;              // rows with the same patch >= 0 and normal stick as one face
};

inline constexpr int kMaxPoints = 16;

struct PointSolution {
  std::array<Vec3, kMaxPoints> P{};  // per point (a patch's friction shared by normal force)
  // Per point: its sticking friction reached its limit (it would slip).
  std::array<bool, kMaxPoints> saturated{};
  Vec3 dv = Vec3::Zero(), dw = Vec3::Zero();  // the body's change of v and w
  Vec3 F = Vec3::Zero(), tau = Vec3::Zero();  // the total and its moment about the centre of mass
  int iterations = 0;
  bool converged = false;
};

// Solves the laws for rows[0 .. n) of one body (n <= kMaxPoints). w0: the body's angular velocity
// (or acceleration) before the solve, which the points' u_W were made from: a patch's twist.
PointSolution solve_points(const Response& body, const PointRow* rows, int n,
                           const Vec3& w0 = Vec3::Zero());

}  // namespace rigid::physics::contact
