#include "physics/contact/island_solver.hpp"

#include <algorithm>
#include <cmath>

namespace rigid::physics::contact {

namespace {

void tangents(const Vec3& n, Vec3& t1, Vec3& t2) {
  const double sign = std::copysign(1.0, n.z());
  const double a = -1.0 / (sign + n.z());
  const double b = n.x() * n.y() * a;
  t1 = Vec3(1.0 + sign * n.x() * n.x() * a, sign * b, -sign * n.x());
  t2 = Vec3(b, sign + n.y() * n.y() * a, -n.y());
}

}  // namespace

IslandResult solve_island(std::span<IslandBody> bodies, std::span<IslandRow> rows,
                          int max_iterations, double rel_tol) {
  IslandResult out;
  const int n = static_cast<int>(rows.size());
  if (n == 0) {
    out.converged = true;
    return out;
  }
  // Per row its tangents, normal response and tangential 2x2 inverse, fixed for the solve (the
  // bodies' orientations do not change in it).
  const auto K_of = [&](const IslandRow& r) {
    Mat3 K = bodies[r.a].resp.K(r.r_a, r.r_a);
    if (r.b >= 0) K += bodies[r.b].resp.K(r.r_b, r.r_b);
    return K;
  };
  const auto apply = [&](const IslandRow& r, const Vec3& P) {
    IslandBody& A = bodies[r.a];
    A.v += A.resp.dv(P);
    A.w += A.resp.dw(r.r_a, P);
    if (r.b >= 0) {
      IslandBody& B = bodies[r.b];
      B.v -= B.resp.dv(P);
      B.w -= B.resp.dw(r.r_b, P);
    }
  };
  const auto u_of = [&](const IslandRow& r) {
    const IslandBody& A = bodies[r.a];
    Vec3 u = A.v + A.w.cross(r.r_a);
    if (r.b >= 0) {
      const IslandBody& B = bodies[r.b];
      u -= B.v + B.w.cross(r.r_b);
    }
    return u;
  };
  double scale = 0.0;
  for (int i = 0; i < n; ++i) {
    IslandRow& r = rows[i];
    IslandRow& c = r;
    tangents(r.n, c.t1, c.t2);
    const Mat3 K = K_of(r);
    c.k_n = r.n.dot(K * r.n);
    Eigen::Matrix<double, 3, 2> T;
    T.col(0) = c.t1;
    T.col(1) = c.t2;
    const Eigen::Matrix2d Ktt = T.transpose() * K * T;
    c.sticks = r.mu > 0.0 && Ktt.determinant() > 0.0;
    if (c.sticks) c.Ktt_inv = Ktt.inverse();
    // Warm start: the impulses carried in act first.
    if (r.pn != 0.0 || r.pt.x() != 0.0 || r.pt.y() != 0.0)
      apply(r, r.pn * r.n + r.pt.x() * c.t1 + r.pt.y() * c.t2);
    scale = std::max({scale, u_of(r).norm(), std::abs(r.target)});
  }
  const double tol = rel_tol * std::max(scale, 1e-300);
  for (int it = 0; it < max_iterations; ++it) {
    out.iterations = it + 1;
    for (int i = 0; i < n; ++i) {
      IslandRow& r = rows[i];
      const IslandRow& c = r;
      if (c.k_n <= 0.0) continue;
      const double un = r.n.dot(u_of(r));
      const double p = std::max(0.0, r.pn + (r.target - un) / c.k_n);
      if (p != r.pn) apply(r, (p - r.pn) * r.n);
      r.pn = p;
      if (!c.sticks) continue;
      const Vec3 u = u_of(r);
      Eigen::Vector2d q = r.pt - c.Ktt_inv * Eigen::Vector2d(c.t1.dot(u), c.t2.dot(u));
      const double limit = r.mu * r.pn, len = q.norm();
      if (len > limit) q *= len > 0.0 ? limit / len : 0.0;
      const Eigen::Vector2d d = q - r.pt;
      if (d.x() != 0.0 || d.y() != 0.0) apply(r, d.x() * c.t1 + d.y() * c.t2);
      r.pt = q;
    }
    double worst = 0.0;
    for (int i = 0; i < n && worst <= tol; ++i) {
      const IslandRow& r = rows[i];
      const IslandRow& c = r;
      if (c.k_n <= 0.0) continue;
      const Vec3 u = u_of(r);
      const double gap = r.n.dot(u) - r.target;
      worst = std::max(worst, r.pn > 0.0 ? std::abs(gap) : std::max(0.0, -gap));
      if (c.sticks && r.pt.norm() < r.mu * r.pn * (1.0 - 1e-12))
        worst = std::max(worst, std::hypot(c.t1.dot(u), c.t2.dot(u)));
    }
    if (worst <= tol) {
      out.converged = true;
      break;
    }
  }
  return out;
}

}  // namespace rigid::physics::contact
