// The exact motion of a torque-free rigid body (Euler-Poinsot), one step at a time.
//
// In the principal frame P (moments I1 < I2 < I3, all distinct) the body angular momentum m
// follows Jacobi elliptic functions (Landau & Lifshitz, Mechanics, section 37), and the
// orientation follows from m and one angle psi about the fixed world momentum L_W. The approach is
// that of Celledoni, Fasso, Safstrom & Zanna, "The exact computation of the free rigid body motion
// and its use in splitting methods", SIAM J. Sci. Comput. 30 (2008), with three choices of ours
// that make a step cheap and exact to round-off at any step size:
//  - the phase is never inverted (no incomplete integral F(phi, k)): the step advances
//    sn, cn, dn of the current phase by the addition theorem (DLMF 22.8.1-3) with sn, cn, dn of
//    the phase increment lambda h;
//  - the frame that takes m to the L axis is the minimal rotation, which makes the rate of psi
//    an analytic function of dn alone, psi' = s (2T/G - a b lambda dn / (G (G + c dn))), regular
//    for every motion including the pure spins;
//  - on short steps (|lambda h| <= 0.05) the increment of psi is integrated by Gauss-Legendre
//    quadrature with the node count chosen from the width of the function's strip of analyticity
//    (its singularities lie at distance > K' >= pi/2 from the real axis), so the quadrature error
//    is below round-off; on long steps it is taken in closed form, Carlson's R_F and R_J at both
//    ends (free_rotor.cpp, "Long steps"), at a cost that does not grow with the step.
// Everything that depends only on the conserved |m|, energy and h is a RotorPlan, computed once
// and reused for as long as no torque changes m: a torque-free body then costs one addition
// theorem, a few quadrature nodes and two quaternion products per step.
#pragma once

#include "physics/math.hpp"

namespace rigid::physics {

// Constants of the rotor that depend only on the principal moments.
struct RotorInertia {
  RotorInertia() = default;
  // I: principal moments, strictly ascending.
  explicit RotorInertia(const Vec3& I);
  Vec3 I = Vec3::Ones();
  double k1 = 0, k3 = 0;      // 1 - I2/I1 (<= 0), 1 - I2/I3 (>= 0): G^2 - 2T I2 = k1 m1^2 + k3 m3^2
  double rA = 0, rhoA = 0;    // I1(I3-I2)/(I2(I3-I1)), I3(I2-I1)/(I2(I3-I1))
  double isrA = 0, isrB = 0;  // 1/sqrt(rA), 1/sqrt(rhoA)
  double srA = 0, srB = 0;    // sqrt(rA), sqrt(rhoA)
  double qA = 0, qB = 0;      // rhoA / rA and its inverse: k^2 = q a^2 / c^2
  double ellA = 0, ellB = 0;  // lambda = c * ell in each case
  Vec3 inv_I = Vec3::Ones();
};

// Everything about a step of length h that does not depend on the phase of the motion.
struct RotorPlan {
  bool still = true;    // m == 0: nothing moves
  bool case_b = false;  // motion about the axis of least inertia (coordinates permuted)
  double s = 1;         // sign of the momentum component on the case's stable axis
  double a = 0, b = 0, c = 0, ia = 0, ib = 0, ic = 0, cn_bias = 0;
  double m = 0, mc = 1;                          // parameter k^2 and its complement k'^2 = 1 - k^2
  double G = 0, iG = 0, lin = 0;                 // |m|, 1 / |m|, 2T h / G
  double abG2 = 0, cG = 0;                       // a b / G^2, c / G
  double S = 0, C = 1, D = 1, mS2 = 0, mSC = 0;  // sn, cn, dn of X = lambda h; m S^2; m S C
  double Cm1 = 0, Dm1 = 0;                       // C - 1, D - 1 to full relative accuracy
  double X = 0;                                  // phase increment lambda h
  int n = 0;  // quadrature nodes cached here (0: a long step, evaluated directly)
  double w[4]{}, Dn[4]{}, mS2n[4]{}, mSCn[4]{};
  // A long step's psi in closed form (free_rotor.cpp, "Long steps"): q = rho / r of the case,
  // 1 / sqrt r, sqrt(1 + q), (q + m) / 3, K(m) and the complete J(pi/2). closed == false: the
  // long step integrates psi panel by panel instead (near the separatrix, or q too large).
  bool closed = false;
  double q = 0, isr = 0, sq = 1, qm3 = 0, K = 0, Jc = 0;
};

// Builds the plan for a step of length h from momentum m (expressed in P). Any h: short steps
// (|lambda h| <= 0.05) cache their quadrature nodes and use the addition theorem; long ones
// evaluate the phase directly and psi in closed form, at a cost that does not grow with h.
void make_rotor_plan(const RotorInertia& J, const Vec3& m_P, double h, RotorPlan& p);

// How advance_rotor forms the new momentum.
//  kPinned: m = amplitudes x new phase. The invariants are those of the plan, exactly: for a plan
//    reused over many steps (a torque-free body), nothing drifts.
//  kIncrement: m += amplitudes x (new phase - old phase), the departures carried to full relative
//    accuracy. For a plan used once (a torqued body, whose invariants change anyway): the
//    round-off is relative to the small increment, where kPinned would round-trip all of m
//    through amplitudes rebuilt from m (a systematic 1e-16 per step: 1e-11 after 5e4 steps).
enum class RotorUpdate { kPinned, kIncrement };

// Advances m_P by the planned step and returns the body-frame rotation increment dq:
// q_WP(t + h) = q_WP(t) * dq. m_P must have the invariants the plan was made for.
void advance_rotor(const RotorPlan& p, Vec3& m_P, Quat& dq,
                   RotorUpdate update = RotorUpdate::kPinned);

// One exact step of any length h, with a plan of its own (RotorUpdate::kIncrement).
void free_rotor_step(const RotorInertia& J, Vec3& m_P, double h, Quat& dq);

// The axisymmetric rotor, moments (A, A, C) with the symmetry axis along z of P: regular
// precession in closed form. m_P(t) turns about z at Omega = (C - A) m3 / (A C), and
// q_WP(t + h) = q_WP(t) * exp(h m_P / A) * exp(-h Omega z).
struct AxisymPlan {
  double cw = 1, hA = 0;  // exp(h m / A) = (cw, hA m): cos(h|m|/2A) and sin(h|m|/2A) / |m|
  double cz = 1, sz = 0;  // cos, sin of h Omega / 2
  double c2 = 1, s2 = 0;  // cos, sin of h Omega
  double inv_perp2 = 0;   // 1 / |m_perp|^2 at planning: the transverse momentum's size is pinned
};
void make_axisym_plan(double A, double C, const Vec3& m_P, double h, AxisymPlan& p);
void advance_axisym(const AxisymPlan& p, Vec3& m_P, Quat& dq);

}  // namespace rigid::physics
