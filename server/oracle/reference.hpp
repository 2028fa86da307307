// An independent oracle for the physics tests: classical RK4 in long double on one body's full
// state, written from the Newton-Euler equations without any of the library's code, run at a
// step small enough that its own error is far below what the tests compare.
//   x' = v,  v' = g + (f_W + R f_B) / m - (c/m) v
//   q' = q x [0, w_B] / 2,  I w_B' = tau_B - w_B x I w_B - k w_B
//   tau_B = r_B x f_B + R^T ((R r_B) x f_W) + tau_B0
// (B is a principal frame here: I diagonal.)
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

namespace rigid::test {

using LD = long double;
using V3 = Eigen::Matrix<LD, 3, 1>;
using Q4 = Eigen::Quaternion<LD>;

struct RefBody {
  V3 I = V3::Ones();  // principal moments
  LD mass = 1;
  LD c = 0, k = 0;  // linear and angular drag
  V3 g = V3::Zero();
  V3 f_B = V3::Zero(), r_fB = V3::Zero();  // body-frame force at body point
  V3 f_W = V3::Zero(), r_fW = V3::Zero();  // world-frame force at body point
  V3 tau_B0 = V3::Zero();                  // pure body-frame torque
};

struct RefState {
  V3 x = V3::Zero(), v = V3::Zero();
  Q4 q = Q4::Identity();
  V3 w = V3::Zero();  // body frame
};

inline RefState ref_deriv(const RefBody& b, const RefState& s) {
  RefState d;
  const Q4 qn = s.q.normalized();
  const Eigen::Matrix<LD, 3, 3> R = qn.toRotationMatrix();
  d.x = s.v;
  d.v = b.g + (b.f_W + R * b.f_B) / b.mass - (b.c / b.mass) * s.v;
  const V3 tau = b.r_fB.cross(b.f_B) + R.transpose() * (R * b.r_fW).cross(b.f_W) + b.tau_B0 -
                 s.w.cross(b.I.cwiseProduct(s.w)) - b.k * s.w;
  d.w = tau.cwiseQuotient(b.I);
  const Q4 wq(0, s.w.x(), s.w.y(), s.w.z());
  d.q.coeffs() = LD(0.5) * (s.q * wq).coeffs();
  return d;
}

inline RefState ref_axpy(const RefState& s, const RefState& d, LD h) {
  RefState r;
  r.x = s.x + h * d.x;
  r.v = s.v + h * d.v;
  r.w = s.w + h * d.w;
  r.q.coeffs() = s.q.coeffs() + h * d.q.coeffs();
  return r;
}

// Advances s by total time T with n RK4 steps.
inline void ref_run(const RefBody& b, RefState& s, LD T, long n) {
  const LD h = T / n;
  for (long i = 0; i < n; ++i) {
    const RefState k1 = ref_deriv(b, s);
    const RefState k2 = ref_deriv(b, ref_axpy(s, k1, h / 2));
    const RefState k3 = ref_deriv(b, ref_axpy(s, k2, h / 2));
    const RefState k4 = ref_deriv(b, ref_axpy(s, k3, h));
    s.x += h / 6 * (k1.x + 2 * k2.x + 2 * k3.x + k4.x);
    s.v += h / 6 * (k1.v + 2 * k2.v + 2 * k3.v + k4.v);
    s.w += h / 6 * (k1.w + 2 * k2.w + 2 * k3.w + k4.w);
    s.q.coeffs() += h / 6 * (k1.q.coeffs() + 2 * k2.q.coeffs() + 2 * k3.q.coeffs() + k4.q.coeffs());
    s.q.normalize();
  }
}

}  // namespace rigid::test

namespace rigid::test {

// A second, independent oracle for torque-free bodies whose motion is so ill-conditioned that
// long double is not enough (near the separatrix, round-off is amplified ~1e12): the Taylor series
// of the Euler equations m' = m x I^-1 m, q' = q x [0, I^-1 m] / 2 in quad precision (__float128,
// 113-bit significand), the coefficients from the Cauchy-product recurrences
//   m_{k+1} = (1/(k+1)) sum_j m_j x w_{k-j},   q_{k+1} = (1/(2(k+1))) sum_j q_j x [0, w_{k-j}].
// Degree `order` with step h; results as long double. No square roots, no library functions.
template <class T>
struct QuadState {
  T q[4];  // w, x, y, z
  T m[3];
};

inline void taylor_free_run(const double I_in[3], const double w0[3], double duration, long steps,
                            int order, long double q_out[4], long double w_out[3]) {
  using Q = __float128;
  const Q I[3] = {I_in[0], I_in[1], I_in[2]};
  const Q iI[3] = {Q(1) / I[0], Q(1) / I[1], Q(1) / I[2]};
  QuadState<Q> s{{1, 0, 0, 0}, {I[0] * Q(w0[0]), I[1] * Q(w0[1]), I[2] * Q(w0[2])}};
  const Q h = Q(duration) / Q(steps);
  constexpr int kMax = 40;
  Q mc[kMax + 1][3], wc[kMax + 1][3], qc[kMax + 1][4];
  for (long n = 0; n < steps; ++n) {
    for (int i = 0; i < 3; ++i)
      mc[0][i] = s.m[i], wc[0][i] = s.m[i] * iI[i];
    for (int i = 0; i < 4; ++i)
      qc[0][i] = s.q[i];
    for (int k = 0; k < order; ++k) {
      Q dm[3] = {0, 0, 0}, dq[4] = {0, 0, 0, 0};
      for (int j = 0; j <= k; ++j) {
        const Q* a = mc[j];
        const Q* w = wc[k - j];
        dm[0] += a[1] * w[2] - a[2] * w[1];
        dm[1] += a[2] * w[0] - a[0] * w[2];
        dm[2] += a[0] * w[1] - a[1] * w[0];
        const Q* q = qc[j];
        dq[0] += -(q[1] * w[0] + q[2] * w[1] + q[3] * w[2]);
        dq[1] += q[0] * w[0] + q[2] * w[2] - q[3] * w[1];
        dq[2] += q[0] * w[1] + q[3] * w[0] - q[1] * w[2];
        dq[3] += q[0] * w[2] + q[1] * w[1] - q[2] * w[0];
      }
      const Q f = Q(1) / Q(k + 1);
      for (int i = 0; i < 3; ++i)
        mc[k + 1][i] = dm[i] * f, wc[k + 1][i] = mc[k + 1][i] * iI[i];
      for (int i = 0; i < 4; ++i)
        qc[k + 1][i] = dq[i] * f * Q(0.5);
    }
    // Horner in h.
    for (int i = 0; i < 3; ++i) {
      Q v = mc[order][i];
      for (int k = order - 1; k >= 0; --k)
        v = v * h + mc[k][i];
      s.m[i] = v;
    }
    for (int i = 0; i < 4; ++i) {
      Q v = qc[order][i];
      for (int k = order - 1; k >= 0; --k)
        v = v * h + qc[k][i];
      s.q[i] = v;
    }
  }
  for (int i = 0; i < 4; ++i)
    q_out[i] = static_cast<long double>(s.q[i]);
  for (int i = 0; i < 3; ++i)
    w_out[i] = static_cast<long double>(s.m[i] / I[i]);
}

}  // namespace rigid::test
