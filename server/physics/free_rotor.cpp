#include "physics/free_rotor.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "physics/elliptic.hpp"
#include "physics/gauss_legendre.hpp"

namespace rigid::physics {

// Derivation (case A: motion about the axis of largest inertia, G^2 > 2T I2; moments J1 < J2 < J3).
// With G = |m| and 2T = sum m_i^2 / J_i, the Euler equations m' = m x J^-1 m are solved by
//   m1 = s a cn(tau), m2 = b sn(tau), m3 = s c dn(tau),  tau = tau0 + lambda t,  s = sign(m3),
// where, written without cancellation (each term below is a sum of non-negative parts),
//   a^2 = m1^2 + r m2^2,  c^2 = m3^2 + rho m2^2,  b^2 = a^2 / r,
//   r = J1 (J3 - J2) / (J2 (J3 - J1)),  rho = J3 (J2 - J1) / (J2 (J3 - J1)),
//   k^2 = rho a^2 / (r c^2),  lambda = c (J3 - J2) / (J2 J3 sqrt(r)).
// These agree with the textbook k^2 = (2T J3 - G^2)(J2 - J1) / ((J3 - J2)(G^2 - 2T J1)) and
// lambda^2 = (J3 - J2)(G^2 - 2T J1) / (J1 J2 J3). Case B (G^2 < 2T I2, about the axis of least
// inertia) is case A in the coordinates m' = (m3, -m2, m1), J' = (I3, I2, I1): a proper rotation
// of P (a half turn about (1, 0, 1)/sqrt 2), where the same formulas hold with lambda < 0.
//
// Orientation: R_WP(t) = Q Rz(psi(t)) P(m(t)) with Q constant and P(m) the minimal rotation taking
// m/G to s e3. Then R(t + h) = R(t) P(m0)^T Rz(dpsi) P(m1): the increment needs only m0, m1 and
// dpsi, and it conserves L_W = R m exactly whatever dpsi is. From R^T R' = [w] with w = J^-1 m one
// finds
//   psi' = s 2T/G - (m1 m2' - m2 m1') / (G (G + s m3)) = s (2T/G - a b lambda dn / (G (G + c dn))),
//   dpsi = s (2T h / G - (a b / G) * integral over [tau0, tau0 + lambda h] of dn / (G + c dn)).

RotorInertia::RotorInertia(const Vec3& I_in) : I(I_in) {
  const double I1 = I.x(), I2 = I.y(), I3 = I.z();
  k1 = 1.0 - I2 / I1;
  k3 = 1.0 - I2 / I3;
  rA = I1 * (I3 - I2) / (I2 * (I3 - I1));
  rhoA = I3 * (I2 - I1) / (I2 * (I3 - I1));
  srA = std::sqrt(rA);
  srB = std::sqrt(rhoA);
  isrA = 1.0 / srA;
  isrB = 1.0 / srB;
  qA = rhoA / rA;
  qB = rA / rhoA;
  inv_I = I.cwiseInverse();
  // Case A: lambda = c (J3 - J2) / (J2 J3 sqrt(r)); case B: J = (I3, I2, I1), r_B = rhoA.
  ellA = (I3 - I2) / (I2 * I3) * isrA;
  ellB = (I1 - I2) / (I2 * I1) * isrB;
}

namespace {

using detail::GaussLegendre;
using detail::kGL2;
using detail::kGL3;
using detail::kGL4;
using detail::kGL6;

// Single-panel rules by panel width |X| (in units of tau). The integrand dn/(G + c dn) is analytic
// for |Im tau| < K' (>= pi/2); with the conservative distance pi/4 the Gauss-Legendre bound
// (64/15) M rho^(-2n) / (rho^2 - 1), rho ~ pi / (2 |X| / 2), stays below 1e-17 relative at these
// widths. Wider steps use panels of kPanel with the 6-point rule.
constexpr double kMaxGL2 = 0.004, kMaxGL3 = 0.02, kMaxGL4 = 0.05, kPanel = 0.15;

const GaussLegendre* single_panel_rule(double absX) {
  if (absX <= kMaxGL2) return &kGL2;
  if (absX <= kMaxGL3) return &kGL3;
  if (absX <= kMaxGL4) return &kGL4;
  return nullptr;
}

// Phase-independent part of the plan: invariants, amplitudes, k^2, lambda, endpoint functions.
void plan_core(const RotorInertia& J, const Vec3& mP, double h, RotorPlan& p, double& X) {
  const double m1 = mP.x(), m2 = mP.y(), m3 = mP.z();
  const double g2 = m1 * m1 + m2 * m2 + m3 * m3;
  // Every field the step reads is assigned below (no zero-fill of the whole plan: its node
  // arrays are written by make_rotor_plan for the nodes in use only).
  X = 0.0;
  p.n = 0;
  p.X = 0.0;
  p.still = g2 == 0.0;
  if (p.still) return;
  p.case_b = J.k1 * m1 * m1 + J.k3 * m3 * m3 < 0.0;
  // Per case: r, rho, 1/sqrt(r), sqrt(r), rho/r, the lambda factor, 1/J in case coordinates.
  double r, rho, isr, sr, q, ell, x1, x2, x3, ij1, ij2, ij3;
  if (p.case_b) {
    r = J.rhoA, rho = J.rA, isr = J.isrB, sr = J.srB, q = J.qB, ell = J.ellB;
    x1 = m3, x2 = -m2, x3 = m1;
    ij1 = J.inv_I.z(), ij2 = J.inv_I.y(), ij3 = J.inv_I.x();
  } else {
    r = J.rA, rho = J.rhoA, isr = J.isrA, sr = J.srA, q = J.qA, ell = J.ellA;
    x1 = m1, x2 = m2, x3 = m3;
    ij1 = J.inv_I.x(), ij2 = J.inv_I.y(), ij3 = J.inv_I.z();
  }
  const double a2 = x1 * x1 + r * x2 * x2;
  const double c2 = x3 * x3 + rho * x2 * x2;
  p.a = std::sqrt(a2);
  p.c = std::sqrt(c2);
  p.G = std::sqrt(g2);
  // One division for 1/a, 1/c and 1/G (c > 0 whenever m != 0, see the case analysis above);
  // b, k^2, k'^2 and 2T come from these and per-body constants.
  double iG;
  const double acg = p.a * p.c * p.G;
  if (std::isnormal(acg)) {
    const double inv = 1.0 / acg;
    p.ia = p.c * p.G * inv;
    p.ic = p.a * p.G * inv;
    iG = p.a * p.c * inv;
  } else {  // a == 0 (a pure spin), or momenta so extreme that the product leaves the range
    p.ia = p.a > 0.0 ? 1.0 / p.a : 0.0;
    p.ic = 1.0 / p.c;
    iG = 1.0 / p.G;
  }
  p.b = p.a * isr;
  p.ib = p.ia * sr;
  p.cn_bias = p.a > 0.0 ? 0.0 : 1.0;  // a == 0: pure spin, any phase; take cn = 1
  p.s = x3 >= 0.0 ? 1.0 : -1.0;
  const double ic2 = p.ic * p.ic;
  p.m = std::min(1.0, q * a2 * ic2);
  // k'^2 = (r c^2 - rho a^2) / (r c^2) = (x3^2 - (rho/r) x1^2) / c^2: the only cancellation left
  // is the physical one, the distance of the motion from the separatrix.
  p.mc = std::max(0.0, (x3 * x3 - q * x1 * x1) * ic2);
  const double two_t = x1 * x1 * ij1 + x2 * x2 * ij2 + x3 * x3 * ij3;
  p.iG = iG;
  p.lin = two_t * h * iG;
  p.abG2 = p.a * p.b * iG * iG;
  p.cG = p.c * iG;
  X = p.c * ell * h;
  p.closed = false;
  if (std::abs(X) > kMaxGL4) {  // a long step never uses the addition theorem
    p.q = q;
    p.isr = isr;
    return;
  }
  const Jacobi e = JacobiSeries(p.m, std::abs(X)).departures(X);
  p.S = e.sn, p.Cm1 = e.cn, p.Dm1 = e.dn;
  p.C = 1.0 + e.cn, p.D = 1.0 + e.dn;
  p.mS2 = p.m * e.sn * e.sn;
  p.mSC = p.m * e.sn * p.C;
}

// The integrand in dimensionless form: G dn / (G + c dn) = dn / (1 + (c/G) dn), so that
// dpsi = s (2T h / G - (a b / G^2) * its integral over the phase increment).
inline double psi_integrand(double cG, double dn) {
  return dn / (1.0 + cG * dn);
}

// Shared tail of a step: the orientation increment from the phases at both ends and dpsi, the
// new momentum y (case coordinates, s y3 = c dn1) mapped back to P. `correction` is (a b / G^2)
// times the integral of dn / (1 + (c/G) dn) over the phase increment.
//
// The frames at both ends are the minimal rotations taking m/G to s e3, (G + s m3, s m2, -s m1,
// 0) / |.| with |.|^2 = 2 G (G + s m3), the start one rebuilt from the phase (s m1 = a cn,
// s m2 = s b sn, s m3 = c dn). Both are left unnormalised, and d = p0^* Rz(dpsi) p1 is scaled
// once: one square root and one division a step, as many as normalising the end frame alone. (The
// end frame was once carried to the next step as its start frame, 24 B a body kept to save a
// square root that this form does not pay; bench/physics/memory_bench.cpp.)
inline void finish_step(const RotorPlan& p, double s0, double c0, double d0, double y1, double y2,
                        double y3, double correction, Vec3& mP, Quat& dq) {
  const double dpsi = p.s * (p.lin - correction);
  double cz, sincz;
  cos_sinc(0.5 * dpsi, cz, sincz);
  const double sz = 0.5 * dpsi * sincz;
  const double w0 = p.G + p.c * d0;
  const double w1 = p.G + p.s * y3;
  const Quat p0(w0, p.s * p.b * s0, -p.a * c0, 0.0);
  const Quat p1(w1, p.s * y2, -p.s * y1, 0.0);
  // u = Rz(dpsi) * p1, with p1.z() == 0; d = p0^* u.
  const Quat u(cz * p1.w(), cz * p1.x() - sz * p1.y(), cz * p1.y() + sz * p1.x(), sz * p1.w());
  Quat d = p0.conjugate() * u;
  d.coeffs() *= 1.0 / (2.0 * p.G * std::sqrt(w0 * w1));
  if (p.case_b) {
    // Back from case coordinates: m = (y3, -y2, y1); a rotation about v' is one about M v'.
    mP = Vec3(y3, -y2, y1);
    dq = Quat(d.w(), d.z(), -d.y(), d.x());
  } else {
    mP = Vec3(y1, y2, y3);
    dq = d;
  }
}

// The phase (sn, cn, dn) of the current momentum, put back on the curve sn^2 + cn^2 = 1,
// dn^2 = k'^2 + k^2 cn^2. Without this, round-off moves the invariants |m| and T a little every
// step; near the separatrix the flip period is so sensitive to them that a 20 s racket flip at
// dt = 1e-4 s lost 7e-9 rad. With it, the invariants are those of the plan, exactly.
inline void phase_of(const RotorPlan& p, double x1, double x2, double x3, bool fresh, double& s0,
                     double& c0, double& d0) {
  s0 = x2 * p.ib;
  c0 = p.s * x1 * p.ia + p.cn_bias;
  if (fresh) {
    // The plan was made from this very m: the phase is on its curve to round-off already.
    d0 = p.s * x3 * p.ic;
    return;
  }
  // One Newton step towards s0^2 + c0^2 = 1: the error is round-off (~1e-16), so this lands on
  // the curve to round-off without a square root; a state set from outside takes the slow path.
  const double n2 = s0 * s0 + c0 * c0;
  const double f = std::abs(n2 - 1.0) < 1e-8 ? 1.5 - 0.5 * n2 : 1.0 / std::sqrt(n2);
  s0 *= f;
  c0 *= f;
  d0 = std::sqrt(p.mc + p.m * c0 * c0);
}

inline void case_coords(const RotorPlan& p, const Vec3& mP, double& x1, double& x2, double& x3) {
  if (p.case_b) {
    x1 = mP.z(), x2 = -mP.y(), x3 = mP.x();
  } else {
    x1 = mP.x(), x2 = mP.y(), x3 = mP.z();
  }
}

// Long steps. In terms of the amplitude phi = am(tau) (d phi = dn d tau, dn = Delta(phi) =
// sqrt(1 - m sin^2 phi)) the psi integral is I = integral of d phi / (1 + g Delta), g = c / G.
// With (1 + g Delta)^-1 = (1 - g Delta) / (1 - g^2 Delta^2) and, from the amplitudes above,
// 1 - g^2 Delta^2 = (a^2 / G^2)(1 + q sin^2 phi), q = rho / r (so that 1 - g^2 = a^2 / G^2 and
// g^2 m = q a^2 / G^2), the correction (a b / G^2) I = (1 / sqrt r) [B(phi1) - B(phi0)] with
//   B(phi) = Theta(phi) / sqrt(1 + q) - g J(phi),
//   Theta(phi) = atan(sqrt(1 + q) tan phi)      = sqrt(1 + q) * integral of d phi / (1 + q sin^2),
//   J(phi) = integral of Delta / (1 + q sin^2) d phi
//          = F(phi) - ((q + m) / 3) sin^3 phi R_J(cos^2 phi, Delta^2, 1, 1 + q sin^2 phi),
// the last from Delta / (1 + q s^2) = [(1 + m/q) / (1 + q s^2) - m/q] / Delta and the third-kind
// integral Pi(-q; phi) = F + (-q / 3) sin^3 phi R_J(...) (DLMF 19.25.14). R_J's last argument
// 1 + q sin^2 phi >= 1: no principal value. Both Theta and J grow by pi and 2 J(pi/2) per half
// period of phi, like F by 2K: a step costs a fixed number of Carlson integrals whatever its
// length, where the panels cost one Jacobi evaluation per 0.025 of phase, which grows with the
// step (bench/notes/step-kernels.md, "Long steps of a free body"). Rounding: B's two terms cancel
// to O(phi) (pure spin: g = 1, m = 0) or lose a factor ~sqrt q (J = F - ..., large q), so J is used
// for q <= kMaxClosedQ only; the separatrix (m = 1, F unbounded) keeps the panels too.
constexpr double kMaxClosedQ = 64.0;

void plan_closed(RotorPlan& p) {
  if (!(p.m < 1.0 && p.mc > 0.0 && p.q <= kMaxClosedQ)) return;
  p.sq = std::sqrt(1.0 + p.q);
  p.qm3 = (p.q + p.m) / 3.0;
  p.K = carlson_rf(0.0, p.mc, 1.0);
  p.Jc = p.K - p.qm3 * carlson_rj(0.0, p.mc, 1.0, 1.0 + p.q);
  p.closed = std::isfinite(p.Jc) && std::isfinite(p.K);
}

// The reduced amplitude phi_r of phi = j pi + phi_r, |phi_r| <= pi/2, by its sine and cosine (c
// >= 0): F(phi_r) and J(phi_r).
struct Reduced {
  double F, J;
};
inline Reduced reduced_integrals(const RotorPlan& p, double s, double c) {
  const double c2 = c * c;
  const double delta2 = p.mc + p.m * c2;  // 1 - m s^2 without cancellation near m = 1
  const double F = s * carlson_rf(c2, delta2, 1.0);
  const double J = F - p.qm3 * s * s * s * carlson_rj(c2, delta2, 1.0, 1.0 + p.q * s * s);
  return {F, J};
}

// The same step as advance_long, psi in closed form. The start phase is (s0, c0) on the curve,
// the end phase tau0 + X.
void advance_long_closed(const RotorPlan& p, double s0, double c0, double d0, Vec3& mP, Quat& dq) {
  // phi0 = j0 pi + phi_r with cos phi_r >= 0.
  const double j0 = c0 >= 0.0 ? 0.0 : (s0 >= 0.0 ? 1.0 : -1.0);
  const double r0s = c0 >= 0.0 ? s0 : -s0, r0c = std::abs(c0);
  const Reduced r0 = reduced_integrals(p, r0s, r0c);
  const double tau0 = 2.0 * j0 * p.K + r0.F;
  const double tau1 = tau0 + p.X;
  const Jacobi e = jacobi(tau1, p.m, p.mc);
  // phi1 = j1 pi + am(tau1 - 2 j1 K), whose sine and cosine are (-1)^j1 (sn, cn)(tau1).
  const double j1 = std::round(tau1 / (2.0 * p.K));
  const double flip = std::fmod(j1, 2.0) == 0.0 ? 1.0 : -1.0;
  const double r1s = flip * e.sn, r1c = flip * e.cn;
  const Reduced r1 = reduced_integrals(p, r1s, r1c);
  // B(phi1) - B(phi0), the whole half periods apart from the rest.
  const double dj = j1 - j0;
  const double dtheta = std::atan2(p.sq * r1s, r1c) - std::atan2(p.sq * r0s, r0c);
  const double half_periods = dj * (std::numbers::pi / p.sq - 2.0 * p.cG * p.Jc);
  const double rest = dtheta / p.sq - p.cG * (r1.J - r0.J);
  const double correction = p.a > 0.0 ? p.isr * (half_periods + rest) : 0.0;
  finish_step(p, s0, c0, d0, p.s * p.a * e.cn, p.b * e.sn, p.s * p.c * e.dn, correction, mP, dq);
}

}  // namespace

void make_rotor_plan(const RotorInertia& J, const Vec3& mP, double h, RotorPlan& p) {
  double X;
  plan_core(J, mP, h, p, X);
  p.X = X;
  if (p.still) return;
  const GaussLegendre* rule = single_panel_rule(std::abs(X));
  if (rule == nullptr) {  // p.n == 0: a long step, see advance_long
    plan_closed(p);
    return;
  }
  const JacobiSeries series(p.m, std::abs(X));
  p.n = rule->n;
  for (int i = 0; i < rule->n; ++i) {
    const Jacobi e = series(0.5 * X * (1.0 + rule->x[i]));
    p.w[i] = 0.5 * X * rule->w[i];
    p.Dn[i] = e.dn;
    p.mS2n[i] = p.m * e.sn * e.sn;
    p.mSCn[i] = p.m * e.sn * e.cn;
  }
}

namespace {

// The integral of psi_integrand over [tau0, tau0 + X] on panels of width <= kPanel.
double integrate_psi(const RotorPlan& p, double tau0, double X) {
  const double n = std::ceil(std::abs(X) / kPanel);
  // X = 0, or NaN (from a non-finite state, which then stays NaN and is the guard's to catch).
  if (!(n >= 1.0)) return 0.0;
  const int panels = static_cast<int>(n);  // callers keep X within kMaxPanels panels
  const double width = X / panels;
  double integral = 0.0;
  for (int k = 0; k < panels; ++k) {
    for (int i = 0; i < kGL6.n; ++i) {
      const double x = width * (k + 0.5 * (1.0 + kGL6.x[i]));
      integral += 0.5 * width * kGL6.w[i] * psi_integrand(p.cG, jacobi(tau0 + x, p.m, p.mc).dn);
    }
  }
  return integral;
}

// A step whose phase advance needs more panels than this (|X| > 1.5e4: a spin of ~1e7 rad/s at
// dt = 1 ms, from a scene file or from torques) integrates whole periods of dn, 2K(m), as one
// period each, and only the rest panel by panel. Before, the panel count overflowed int (undefined
// behaviour, found by fuzzing) or the step ran for hours. Shorter steps are computed as before.
constexpr double kMaxPanels = 1e5;

// A long step (|X| > kMaxGL4). The addition theorem would cancel catastrophically here (its
// denominator 1 - m sn^2(tau0) sn^2(X) tends to k'^2 when both phases approach K near the
// separatrix: 2e-9 lost in one 4 s step of the racket flip), so the phase is taken explicitly,
// tau0 = F(am | m), and the functions are evaluated at tau0 + x directly. psi: panels of width
// <= kPanel with the 6-point rule.
void advance_long(const RotorPlan& p, double s0, double c0, double d0, Vec3& mP, Quat& dq) {
  const double tau0 = elliptic_f(std::atan2(s0, c0), p.m, p.mc);
  double integral = 0.0;
  if (std::abs(p.X) <= kMaxPanels * kPanel) {
    integral = integrate_psi(p, tau0, p.X);
  } else {
    const double period = 2.0 * elliptic_k(p.m);
    if (std::isfinite(period)) {
      const double rest = std::fmod(p.X, period);  // exact, |rest| < period
      integral =
          (p.X - rest) / period * integrate_psi(p, tau0, period) + integrate_psi(p, tau0, rest);
    } else {
      // m = 1, the separatrix: no period, but dn = sech decays and the integrand with it, to
      // below round-off long before this phase.
      integral = integrate_psi(p, tau0, std::copysign(kMaxPanels * kPanel, p.X));
    }
  }
  const Jacobi e = jacobi(tau0 + p.X, p.m, p.mc);
  finish_step(p, s0, c0, d0, p.s * p.a * e.cn, p.b * e.sn, p.s * p.c * e.dn, p.abG2 * integral, mP,
              dq);
}

}  // namespace

void advance_rotor(const RotorPlan& p, Vec3& mP, Quat& dq, RotorUpdate update) {
  if (p.still) {
    dq = Quat::Identity();
    return;
  }
  double x1, x2, x3;
  case_coords(p, mP, x1, x2, x3);
  double s0, c0, d0;
  phase_of(p, x1, x2, x3, update == RotorUpdate::kIncrement, s0, c0, d0);
  if (p.n == 0) {
    if (p.closed) {
      advance_long_closed(p, s0, c0, d0, mP, dq);
    } else {
      advance_long(p, s0, c0, d0, mP, dq);
    }
    return;
  }
  // Nodes at tau0 + x_i by the addition theorem, dn(u + v) = (dn u dn v - m sn u cn u sn v cn v)
  // / (1 - m sn^2 u sn^2 v). Each term is num_i / (den_i + (c/G) num_i), summed as one fraction:
  // one division instead of n (the denominators all lie in [0.99, 2]).
  double top = 0.0, bottom = 1.0;
  const double sc0 = s0 * c0, ss0 = s0 * s0;
  for (int i = 0; i < p.n; ++i) {
    const double num = d0 * p.Dn[i] - p.mSCn[i] * sc0;
    const double den = (1.0 - p.mS2n[i] * ss0) + p.cG * num;
    top = top * den + p.w[i] * num * bottom;
    bottom *= den;
  }
  const double integral = top / bottom;
  // The addition theorem (DLMF 22.8.1-3). Its denominator 1 - m sn0^2 S^2 stays >= 1 - S^2 >
  // 0.997 on this path (|X| <= 0.05), so it cannot cancel.
  const double e = p.mS2 * ss0;
  const double inv = 1.0 / (1.0 - e);
  if (update == RotorUpdate::kPinned) {
    const double sn1 = (s0 * p.C * p.D + p.S * c0 * d0) * inv;
    const double cn1 = (c0 * p.C - s0 * d0 * p.S * p.D) * inv;
    const double dn1 = (d0 * p.D - p.mSC * sc0) * inv;
    finish_step(p, s0, c0, d0, p.s * p.a * cn1, p.b * sn1, p.s * p.c * dn1, p.abG2 * integral, mP,
                dq);
  } else {
    // The same theorem written for the departures sn1 - sn0, ..., each numerator made of small
    // terms only: C D - 1 + e = Cm1 + Dm1 + Cm1 Dm1 + e, with e = m sn0^2 S^2 = 1 - den.
    const double cdm1 = p.Cm1 + p.Dm1 + p.Cm1 * p.Dm1;
    const double ds = (s0 * (cdm1 + e) + p.S * c0 * d0) * inv;
    const double dc = (c0 * (p.Cm1 + e) - s0 * d0 * p.S * p.D) * inv;
    const double dd = (d0 * (p.Dm1 + e) - p.mSC * sc0) * inv;
    finish_step(p, s0, c0, d0, x1 + p.s * p.a * dc, x2 + p.b * ds, x3 + p.s * p.c * dd,
                p.abG2 * integral, mP, dq);
  }
}

void free_rotor_step(const RotorInertia& J, Vec3& mP, double h, Quat& dq) {
  RotorPlan p;
  make_rotor_plan(J, mP, h, p);
  advance_rotor(p, mP, dq, RotorUpdate::kIncrement);
}

void make_axisym_plan(double A, double C, const Vec3& mP, double h, AxisymPlan& p) {
  // exp(h m / A) as a quaternion: (cos(theta/2), sin(theta/2) m/|m|), theta = h |m| / A.
  double c, sinc;
  cos_sinc(0.5 * h * mP.norm() / A, c, sinc);
  p.cw = c;
  p.hA = 0.5 * h * sinc / A;
  const double omega = (C - A) * mP.z() / (A * C);
  double cz, sincz;
  cos_sinc(0.5 * h * omega, cz, sincz);
  p.cz = cz;
  p.sz = 0.5 * h * omega * sincz;
  p.c2 = cz * cz - p.sz * p.sz;
  p.s2 = 2.0 * cz * p.sz;
  const double perp2 = mP.x() * mP.x() + mP.y() * mP.y();
  p.inv_perp2 = perp2 > 0.0 ? 1.0 / perp2 : 0.0;
}

void advance_axisym(const AxisymPlan& p, Vec3& mP, Quat& dq) {
  const Quat e(p.cw, p.hA * mP.x(), p.hA * mP.y(), p.hA * mP.z());
  dq = e * Quat(p.cz, 0.0, 0.0, -p.sz);
  double m1 = p.c2 * mP.x() - p.s2 * mP.y();
  double m2 = p.s2 * mP.x() + p.c2 * mP.y();
  // (c2, s2) is a rotation only to round-off, the same bias every step: pin |m_perp| back to its
  // planned value with one Newton step on |m_perp|^2 (no square root), or it drifts with N.
  if (p.inv_perp2 > 0.0) {
    const double f = 1.5 - 0.5 * (m1 * m1 + m2 * m2) * p.inv_perp2;
    m1 *= f;
    m2 *= f;
  }
  mP.x() = m1;
  mP.y() = m2;
}

}  // namespace rigid::physics
