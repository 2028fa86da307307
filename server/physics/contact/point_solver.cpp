#include "physics/contact/point_solver.hpp"

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

// A patch: rows [begin, end) sharing a part's face. Its sticking friction: (f1, f2) along the
// tangents at the centre of pressure c, and a moment m about the normal.
struct Patch {
  int begin = 0, end = 0;
  bool sticks = false;  // more than one row, friction, none sliding
  Vec3 t1, t2, n;
  Vec3 c = Vec3::Zero();  // where its friction force acts (from the centre of mass)
  Vec3 f = Vec3::Zero();  // its friction force (W)
  double m = 0.0;         // its friction moment about n
  double mu = 0.0;
  bool saturated = false;
};

}  // namespace

PointSolution solve_points(const Response& body, const PointRow* rows, int n, const Vec3& w0) {
  PointSolution out;
  n = std::min(n, kMaxPoints);
  // Per row: its normal (with its sliding friction) direction and response, and for single
  // sticking rows the basis and 2x2 tangential inverse.
  std::array<Vec3, kMaxPoints> t1, t2, dir;
  std::array<double, kMaxPoints> k_dir{};
  std::array<Eigen::Matrix2d, kMaxPoints> Ktt_inv;
  std::array<bool, kMaxPoints> can_stick{};
  std::array<Patch, kMaxPoints> patches;
  int n_patches = 0;
  for (int i = 0; i < n;) {
    // A patch: the run of rows with this row's patch id and normal.
    int j = i + 1;
    while (rows[i].patch >= 0 && j < n && rows[j].patch == rows[i].patch &&
           rows[j].n_W == rows[i].n_W)
      ++j;
    Patch& p = patches[n_patches++];
    p.begin = i, p.end = j;
    p.n = rows[i].n_W;
    p.mu = rows[i].mu;
    bool any_sliding = false;
    for (int k = i; k < j; ++k)
      any_sliding = any_sliding || rows[k].sliding;
    p.sticks = j - i > 1 && p.mu > 0.0 && !any_sliding;
    tangents(p.n, p.t1, p.t2);
    i = j;
  }
  for (int pi = 0; pi < n_patches; ++pi) {
    const Patch& p = patches[pi];
    for (int i = p.begin; i < p.end; ++i) {
      const PointRow& row = rows[i];
      const Mat3 K = body.K(row.r_W, row.r_W);
      tangents(row.n_W, t1[i], t2[i]);
      dir[i] = row.sliding ? Vec3(row.n_W - row.mu * row.slip_W) : row.n_W;
      k_dir[i] = row.n_W.dot(K * dir[i]);
      // Sliding friction that would pull the point into the part as the normal force grows (the
      // Painleve configurations): no force law holds there; the normal alone is taken, and the
      // caller stops the slip by an impulse first (contact_step.cpp).
      if (row.sliding && k_dir[i] <= 0.0) {
        dir[i] = row.n_W;
        k_dir[i] = row.n_W.dot(K * dir[i]);
      }
      Eigen::Matrix<double, 3, 2> T;
      T.col(0) = t1[i];
      T.col(1) = t2[i];
      const Eigen::Matrix2d Ktt = T.transpose() * K * T;
      can_stick[i] = !p.sticks && !row.sliding && row.mu > 0.0 && Ktt.determinant() > 0.0;
      if (can_stick[i]) Ktt_inv[i] = Ktt.inverse();
    }
  }
  std::array<double, kMaxPoints> pn{};
  std::array<Eigen::Vector2d, kMaxPoints> pt;
  for (int i = 0; i < n; ++i)
    pt[i].setZero();
  const auto u_at = [&](const Vec3& u0, const Vec3& r) {
    return Vec3(u0 + out.dv + out.dw.cross(r));
  };
  const auto u_of = [&](int i) { return u_at(rows[i].u_W, rows[i].r_W); };
  const auto apply = [&](const Vec3& r, const Vec3& dP) {
    out.dv += body.dv(dP);
    out.dw += body.dw(r, dP);
  };
  const auto apply_moment = [&](const Vec3& M) { out.dw += body.inv_I_W * M; };
  // A patch's friction is solved at its centre of pressure from the velocity there: the velocity
  // of the body's point at c, which rows' u_W give by their rigid-body relation (u_W = v + w x r
  // plus terms that do not depend on the solve: the same at every row of a patch).
  const auto patch_u = [&](const Patch& p, const Vec3& c) {
    const PointRow& r0 = rows[p.begin];
    const Vec3 w = w0 + out.dw;
    // u at c = u at row 0 + w x (c - r0), with u at row 0 as the solve has made it.
    return Vec3(u_of(p.begin) + w.cross(c - r0.r_W));
  };

  double scale = 0.0;
  for (int i = 0; i < n; ++i)
    scale = std::max({scale, rows[i].u_W.norm(), std::abs(rows[i].target)});
  // Converged when every law holds to round-off of the quantities it is about. Normal impulses
  // may still move where points are redundant (four corners of a face hold three degrees of
  // freedom): any of those distributions acts on the body alike.
  constexpr double kRelTol = 1e-14;
  constexpr int kMaxIterations = 2000;
  const double tol = kRelTol * scale;
  for (int it = 0; it < kMaxIterations; ++it) {
    out.iterations = it + 1;
    for (int pi = 0; pi < n_patches; ++pi) {
      Patch& p = patches[pi];
      for (int i = p.begin; i < p.end; ++i) {
        const PointRow& row = rows[i];
        if (k_dir[i] <= 0.0) continue;  // a point no impulse can move (kinematic, locked)
        const double un = row.n_W.dot(u_of(i));
        const double p_new = std::max(0.0, pn[i] + (row.target - un) / k_dir[i]);
        const double dp = p_new - pn[i];
        if (dp != 0.0) apply(row.r_W, dp * dir[i]);
        pn[i] = p_new;
        if (!can_stick[i]) continue;
        // A single point's sticking friction, within the disk |P_t| <= mu P_n.
        const Vec3 u = u_of(i);
        const Eigen::Vector2d ut(t1[i].dot(u), t2[i].dot(u));
        Eigen::Vector2d q = pt[i] - Ktt_inv[i] * ut;
        const double limit = row.mu * pn[i];
        const double len = q.norm();
        if (len > limit) q *= len > 0.0 ? limit / len : 0.0;
        const Eigen::Vector2d d = q - pt[i];
        if (d.x() != 0.0 || d.y() != 0.0) apply(row.r_W, d.x() * t1[i] + d.y() * t2[i]);
        pt[i] = q;
      }
      if (!p.sticks) continue;
      // The patch's friction: taken off, then solved again at the new centre of pressure.
      apply(p.c, -p.f);
      apply_moment(-p.m * p.n);
      double N = 0.0;
      Vec3 c = Vec3::Zero();
      for (int i = p.begin; i < p.end; ++i) {
        N += pn[i];
        c += pn[i] * rows[i].r_W;
      }
      p.f.setZero();
      p.m = 0.0;
      p.saturated = false;
      if (N <= 0.0) continue;
      c /= N;
      p.c = c;
      double spread = 0.0;  // the mean distance of the points from c, across the normal
      for (int i = p.begin; i < p.end; ++i) {
        const Vec3 d = rows[i].r_W - c;
        spread += pn[i] * (d - p.n * p.n.dot(d)).norm();
      }
      spread /= N;
      // The response of (u_t1, u_t2, w_n) at c to (f1, f2, m), column by column.
      Mat3 K;
      const Vec3 basis[2] = {p.t1, p.t2};
      for (int k = 0; k < 2; ++k) {
        const Vec3 dv = body.dv(basis[k]), dw = body.dw(c, basis[k]);
        const Vec3 du = dv + dw.cross(c);
        K.col(k) = Vec3(p.t1.dot(du), p.t2.dot(du), p.n.dot(dw));
      }
      {
        const Vec3 dw = body.inv_I_W * p.n;
        const Vec3 du = dw.cross(c);
        K.col(2) = Vec3(p.t1.dot(du), p.t2.dot(du), p.n.dot(dw));
      }
      const Vec3 u = patch_u(p, c);
      const Vec3 rhs(p.t1.dot(u), p.t2.dot(u), p.n.dot(w0 + out.dw));
      Vec3 lam = -K.completeOrthogonalDecomposition().solve(rhs);
      // Coulomb's bounds: the force within mu N, the moment within mu N times the spread.
      const Eigen::Vector2d ft(lam.x(), lam.y());
      const double f_limit = p.mu * N, m_limit = p.mu * N * spread;
      if (ft.norm() > f_limit) {
        lam.x() *= f_limit / ft.norm(), lam.y() *= f_limit / ft.norm();
        p.saturated = true;
      }
      if (std::abs(lam.z()) > m_limit) {
        lam.z() = std::copysign(m_limit, lam.z());
        p.saturated = true;
      }
      p.f = lam.x() * p.t1 + lam.y() * p.t2;
      p.m = lam.z();
      apply(p.c, p.f);
      apply_moment(p.m * p.n);
    }
    // The laws' residuals.
    double worst = 0.0;
    for (int pi = 0; pi < n_patches && worst <= tol; ++pi) {
      const Patch& p = patches[pi];
      for (int i = p.begin; i < p.end; ++i) {
        if (k_dir[i] <= 0.0) continue;
        const Vec3 u = u_of(i);
        const double gap = rows[i].n_W.dot(u) - rows[i].target;
        worst = std::max(worst, pn[i] > 0.0 ? std::abs(gap) : std::max(0.0, -gap));
        if (can_stick[i] && pt[i].norm() < rows[i].mu * pn[i] * (1.0 - 1e-12)) {
          worst = std::max(worst, std::hypot(t1[i].dot(u), t2[i].dot(u)));
        }
      }
      if (p.sticks && !p.saturated && p.f.norm() + std::abs(p.m) > 0.0) {
        const Vec3 u = patch_u(p, p.c);
        worst = std::max(worst, std::hypot(p.t1.dot(u), p.t2.dot(u)));
      }
    }
    if (worst <= tol) {
      out.converged = true;
      break;
    }
  }
  for (int pi = 0; pi < n_patches; ++pi) {
    const Patch& p = patches[pi];
    double N = 0.0;
    for (int i = p.begin; i < p.end; ++i)
      N += pn[i];
    for (int i = p.begin; i < p.end; ++i) {
      out.P[i] = pn[i] * dir[i] + pt[i].x() * t1[i] + pt[i].y() * t2[i];
      if (p.sticks && N > 0.0) out.P[i] += pn[i] / N * p.f;
      out.saturated[i] = p.sticks ? p.saturated
                                  : can_stick[i] && pn[i] > 0.0 &&
                                        pt[i].norm() >= rows[i].mu * pn[i] * (1.0 - 1e-12);
    }
  }
  // The totals: the points' impulses and their moments, and the patches' moments.
  for (int i = 0; i < n; ++i) {
    out.F += out.P[i];
    out.tau += rows[i].r_W.cross(out.P[i]);
  }
  for (int pi = 0; pi < n_patches; ++pi) {
    if (patches[pi].sticks) out.tau += patches[pi].m * patches[pi].n;
  }
  return out;
}

}  // namespace rigid::physics::contact
