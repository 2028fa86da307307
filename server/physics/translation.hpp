// Exact translation under linear drag: the exponential integrator of v' = a(t) - gamma v.
//
// With gamma = c / m and z = -gamma s, the flow over a step s with the acceleration a(t)
// interpolated linearly from a0 to a1 is, exactly (variation of constants),
//   v1 = e^z v0 + s phi1(z) a0 + s phi2(z) (a1 - a0)
//   x1 = x0 + s phi1(z) v0 + s^2 phi2(z) a0 + s^2 phi3(z) (a1 - a0)
// with the phi-functions of exponential integrators, phi_k(z) = sum_j z^j / (j + k)!
// (Hochbruck & Ostermann, "Exponential integrators", Acta Numerica 2010). It is exact for any
// constant acceleration (gravity, world-frame forces) at any c dt / m, and second order when the
// acceleration turns with the body. With gamma = 0 it reduces to x1 = x0 + s v0 + s^2 (a0/2 + ...).
#pragma once

#include <cmath>

#include "physics/math.hpp"

namespace rigid::physics::detail {

struct TransCoef {
  double E = 1, p1 = 0, p2 = 0, q2 = 0, q3 = 0;  // e^z, s phi1, s phi2, s^2 phi2, s^2 phi3
};

// phi_1..3(z) for z <= 0, accurate to round-off (series near 0, closed forms beyond).
inline void phi_functions(double z, double& phi1, double& phi2, double& phi3) {
  if (std::abs(z) < 1.0) {
    // sum_j z^j / (j + k)!, j <= 22: truncation < 1/25! < 1e-25.
    constexpr int kTerms = 22;
    double inv_fact[kTerms + 4];
    inv_fact[0] = 1.0;
    for (int i = 1; i < kTerms + 4; ++i)
      inv_fact[i] = inv_fact[i - 1] / i;
    double t1 = 0, t2 = 0, t3 = 0;
    for (int j = kTerms; j >= 0; --j) {
      t1 = t1 * z + inv_fact[j + 1];
      t2 = t2 * z + inv_fact[j + 2];
      t3 = t3 * z + inv_fact[j + 3];
    }
    phi1 = t1, phi2 = t2, phi3 = t3;
    return;
  }
  const double em1 = std::expm1(z);
  phi1 = em1 / z;
  phi2 = (em1 - z) / (z * z);
  phi3 = (em1 - z - 0.5 * z * z) / (z * z * z);
}

inline TransCoef trans_coef(double gamma, double s) {
  const double z = -gamma * s;
  double f1, f2, f3;
  phi_functions(z, f1, f2, f3);
  return {std::exp(z), s * f1, s * f2, s * s * f2, s * s * f3};
}

// One exact step of the drag flow with linearly interpolated acceleration. (Always inlined, as
// the kernels' other small steps: a few vector operations, which a call would double.)
[[gnu::always_inline]] inline void translate(const TransCoef& k, const Vec3& a0, const Vec3& a1,
                                             Vec3& x, Vec3& v) {
  const Vec3 da = a1 - a0;
  x += k.p1 * v + k.q2 * a0 + k.q3 * da;
  v = k.E * v + k.p1 * a0 + k.p2 * da;
}

// The same for a constant acceleration (a0 == a1): exact.
[[gnu::always_inline]] inline void translate(const TransCoef& k, const Vec3& a, Vec3& x, Vec3& v) {
  x += k.p1 * v + k.q2 * a;
  v = k.E * v + k.p1 * a;
}

// The kick sub-flow of a splitting: v' = a - gamma v with a constant, exact.
[[gnu::always_inline]] inline void kick(const TransCoef& k, const Vec3& a, Vec3& v) {
  v = k.E * v + k.p1 * a;
}

}  // namespace rigid::physics::detail
