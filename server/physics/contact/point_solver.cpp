#include "physics/contact/point_solver.hpp"

#include <algorithm>
#include <cmath>

namespace rigid::physics::contact {

namespace {

// Two unit tangents completing n to an orthonormal basis (Frisvad's construction with the
// singularity moved away from n = -z: Duff et al., JCGT 6(1), 2017).
void tangents(const Vec3& n, Vec3& t1, Vec3& t2) {
  const double sign = std::copysign(1.0, n.z());
  const double a = -1.0 / (sign + n.z());
  const double b = n.x() * n.y() * a;
  t1 = Vec3(1.0 + sign * n.x() * n.x() * a, sign * b, -sign * n.x());
  t2 = Vec3(b, sign + n.y() * n.y() * a, -n.y());
}

}  // namespace

PointSolution solve_points(const Response& body, const PointRow* rows, int n) {
  PointSolution out;
  n = std::min(n, kMaxPoints);
  // Per row: its own K block, the basis (n, t1, t2) and the 2x2 tangential inverse.
  std::array<Mat3, kMaxPoints> Kii;
  std::array<Vec3, kMaxPoints> t1, t2, dir;
  std::array<double, kMaxPoints> k_dir{};
  std::array<Eigen::Matrix2d, kMaxPoints> Ktt_inv;
  std::array<bool, kMaxPoints> can_stick{};
  for (int i = 0; i < n; ++i) {
    const PointRow& row = rows[i];
    Kii[i] = body.K(row.r_W, row.r_W);
    tangents(row.n_W, t1[i], t2[i]);
    // The impulse's direction per unit normal impulse: the normal alone, or with the sliding
    // friction it brings.
    dir[i] = row.sliding ? Vec3(row.n_W - row.mu * row.slip_W) : row.n_W;
    k_dir[i] = row.n_W.dot(Kii[i] * dir[i]);
    Eigen::Matrix<double, 3, 2> T;
    T.col(0) = t1[i];
    T.col(1) = t2[i];
    const Eigen::Matrix2d Ktt = T.transpose() * Kii[i] * T;
    can_stick[i] = !row.sliding && row.mu > 0.0 && Ktt.determinant() > 0.0;
    if (can_stick[i]) Ktt_inv[i] = Ktt.inverse();
  }
  std::array<double, kMaxPoints> pn{};  // normal impulse (along dir for sliding rows)
  std::array<Eigen::Vector2d, kMaxPoints> pt;
  for (int i = 0; i < n; ++i)
    pt[i].setZero();
  const auto u_of = [&](int i) { return Vec3(rows[i].u_W + out.dv + out.dw.cross(rows[i].r_W)); };
  const auto apply = [&](int i, const Vec3& dP) {
    out.dv += body.dv(dP);
    out.dw += body.dw(rows[i].r_W, dP);
  };
  // Converged when no impulse changed by more than this share of the largest.
  constexpr double kRelTol = 1e-15;
  constexpr int kMaxIterations = 2000;
  for (int it = 0; it < kMaxIterations; ++it) {
    out.iterations = it + 1;
    double change = 0.0, size = 0.0;
    for (int i = 0; i < n; ++i) {
      const PointRow& row = rows[i];
      if (k_dir[i] <= 0.0) continue;  // a point that no impulse can move (kinematic, locked)
      // Normal (with its sliding friction).
      const double un = row.n_W.dot(u_of(i));
      const double p_new = std::max(0.0, pn[i] + (row.target - un) / k_dir[i]);
      const double dp = p_new - pn[i];
      if (dp != 0.0) apply(i, dp * dir[i]);
      change = std::max(change, std::abs(dp));
      pn[i] = p_new;
      // Sticking friction: cancel the tangential motion, within the disk |P_t| <= mu P_n.
      if (can_stick[i]) {
        const Vec3 u = u_of(i);
        const Eigen::Vector2d ut(t1[i].dot(u), t2[i].dot(u));
        Eigen::Vector2d p = pt[i] - Ktt_inv[i] * ut;
        const double limit = row.mu * pn[i];
        const double len = p.norm();
        if (len > limit) p *= len > 0.0 ? limit / len : 0.0;
        const Eigen::Vector2d d = p - pt[i];
        if (d.x() != 0.0 || d.y() != 0.0) apply(i, d.x() * t1[i] + d.y() * t2[i]);
        change = std::max(change, d.norm());
        pt[i] = p;
      }
      size = std::max(size, pn[i] + pt[i].norm());
    }
    if (change <= kRelTol * size) {
      out.converged = true;
      break;
    }
  }
  for (int i = 0; i < n; ++i)
    out.P[i] = pn[i] * dir[i] + pt[i].x() * t1[i] + pt[i].y() * t2[i];
  return out;
}

}  // namespace rigid::physics::contact
