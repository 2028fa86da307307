// Small fixed-size math on top of Eigen: the types the physics uses, and the quaternion helpers
// the integrators share. Quaternions are Hamilton, stored (w, x, y, z) in our APIs; q maps vectors
// from the body frame to the world frame: v_W = q * v_B * conj(q).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

namespace rigid::physics {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Quat = Eigen::Quaterniond;

// sin(x)/x and (1 - cos x)/x^2 style helpers need a series near zero; below this angle the
// truncated series is exact to round-off (next term < 1e-20 relative).
inline constexpr double kSmallAngle = 1.0 / 16.0;

// cos(t) and sin(t)/t for the half angle of a rotation vector: accurate for all t, and free of
// libm calls when |t| is small, which is the common case inside a time step.
inline void cos_sinc(double t, double& c, double& sinc) {
  const double t2 = t * t;
  const double at = std::abs(t);
  // Taylor series, as short as the angle allows: the first omitted term stays below 1e-20.
  if (at < 1e-3) {  // next terms t^6/720, t^6/5040 < 1.4e-21
    c = 1.0 + t2 * (-1.0 / 2 + t2 * (1.0 / 24));
    sinc = 1.0 + t2 * (-1.0 / 6 + t2 * (1.0 / 120));
  } else if (at < 2e-2) {  // next terms t^10/10!, t^10/11! < 3e-24
    c = 1.0 + t2 * (-1.0 / 2 + t2 * (1.0 / 24 + t2 * (-1.0 / 720 + t2 * (1.0 / 40320))));
    sinc = 1.0 + t2 * (-1.0 / 6 + t2 * (1.0 / 120 + t2 * (-1.0 / 5040 + t2 * (1.0 / 362880))));
  } else if (at < kSmallAngle) {  // next terms t^14/14! < 1e-27
    c = 1.0 + t2 * (-1.0 / 2 +
                    t2 * (1.0 / 24 +
                          t2 * (-1.0 / 720 + t2 * (1.0 / 40320 + t2 * (-1.0 / 3628800 +
                                                                       t2 * (1.0 / 479001600))))));
    sinc = 1.0 +
           t2 * (-1.0 / 6 +
                 t2 * (1.0 / 120 + t2 * (-1.0 / 5040 +
                                         t2 * (1.0 / 362880 + t2 * (-1.0 / 39916800 +
                                                                    t2 * (1.0 / 6227020800.0))))));
  } else {
    c = std::cos(t);
    sinc = std::sin(t) / t;
  }
}

// cos(t) and sin(t)/t from t^2 alone: no square root while |t| < kSmallAngle (the same series as
// cos_sinc, chosen by t^2), so that a rotation by a vector needs no norm.
inline void cos_sinc_sq(double t2, double& c, double& sinc) {
  if (t2 < kSmallAngle * kSmallAngle) {  // next terms t^14/14! < 1e-27
    c = 1.0 + t2 * (-1.0 / 2 +
                    t2 * (1.0 / 24 +
                          t2 * (-1.0 / 720 + t2 * (1.0 / 40320 + t2 * (-1.0 / 3628800 +
                                                                       t2 * (1.0 / 479001600))))));
    sinc = 1.0 +
           t2 * (-1.0 / 6 +
                 t2 * (1.0 / 120 + t2 * (-1.0 / 5040 +
                                         t2 * (1.0 / 362880 + t2 * (-1.0 / 39916800 +
                                                                    t2 * (1.0 / 6227020800.0))))));
  } else {
    const double t = std::sqrt(t2);
    c = std::cos(t);
    sinc = std::sin(t) / t;
  }
}

// q * v * conj(q) for a unit q: the operations of Eigen's QuaternionBase::_transformVector in
// the same order (uv = 2 (q_v x v); v + w uv + q_v x uv), so the same bits as `q * v`, written
// on scalars so that it inlines. Eigen's is called out of line, and its argument, stored by the
// caller just before, reached it through a stalled store forward: three quarters of the cost of
// World::write_states (bench/step_bench --benchmark_filter=write_states).
inline Vec3 rotate(const Quat& q, const Vec3& v) {
  const double qw = q.w(), qx = q.x(), qy = q.y(), qz = q.z();
  const double vx = v.x(), vy = v.y(), vz = v.z();
  double ux = qy * vz - qz * vy, uy = qz * vx - qx * vz, uz = qx * vy - qy * vx;
  ux += ux, uy += uy, uz += uz;
  return Vec3(vx + qw * ux + (qy * uz - qz * uy), vy + qw * uy + (qz * ux - qx * uz),
              vz + qw * uz + (qx * uy - qy * ux));
}

// The unit quaternion of the rotation vector phi (angle |phi| about phi/|phi|): exp(phi/2).
inline Quat quat_exp(const Vec3& phi) {
  double c, sinc;
  cos_sinc(0.5 * phi.norm(), c, sinc);
  const Vec3 v = (0.5 * sinc) * phi;
  return Quat(c, v.x(), v.y(), v.z());
}

// Pulls |q| back to 1. One Newton step on |q|^2 = 1: exact to round-off when |q| is within
// ~1e-8 of 1 (the integrators' case), and falls back to a full normalisation otherwise.
inline void renormalize(Quat& q) {
  const double n2 = q.squaredNorm();
  const double e = n2 - 1.0;
  if (std::abs(e) < 1e-8) {
    q.coeffs() *= 1.5 - 0.5 * n2;
  } else {
    q.coeffs() /= std::sqrt(n2);
  }
}

inline Mat3 skew(const Vec3& v) {
  Mat3 m;
  m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return m;
}

}  // namespace rigid::physics
