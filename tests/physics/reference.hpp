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
