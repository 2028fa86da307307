// The exact free rotor against an independent long-double RK4 solution of the Euler equations,
// across both cases of the motion (about the axis of least and of greatest inertia), the
// separatrix neighbourhood, pure spins, any step length, and its conservation laws.
#include "physics/free_rotor.hpp"

#include <gtest/gtest.h>

#include "test_util.hpp"

namespace rigid::test {
namespace {

using physics::AxisymPlan;
using physics::RotorInertia;
using physics::RotorPlan;

struct Motion {
  Vec3 I;
  Vec3 w0;
};

// Case A (about the axis of greatest inertia), case B (least), near the separatrix, a thin body.
const Motion kMotions[] = {
    {{1, 2, 3}, {0.3, 0.1, 2.0}},        {{1, 2, 3}, {1.5, 0.2, 0.3}},
    {{1, 2, 3}, {1e-3, 5.0, 1e-3}},      {{0.5, 1.3, 1.7}, {20.0, 0.5, 20.0}},
    {{1e-3, 1.0, 1.0005}, {50, 1, 0.2}}, {{2, 2.5, 4}, {-1.0, 3.0, -2.0}},
};

struct RotorRun {
  Quat q = Quat::Identity();
  Vec3 m;
};

// Steps with the plan cached for the whole run (the integrators' torque-free path).
RotorRun run_cached(const Motion& c, double h, long n) {
  const RotorInertia J(c.I);
  RotorRun r{Quat::Identity(), c.I.cwiseProduct(c.w0)};
  RotorPlan p;
  physics::make_rotor_plan(J, r.m, h, p);
  for (long i = 0; i < n; ++i) {
    Quat dq;
    physics::advance_rotor(p, r.m, dq);
    r.q = r.q * dq;
    physics::renormalize(r.q);
  }
  return r;
}

TEST(FreeRotor, MatchesTheReferenceSolution) {
  for (const Motion& c : kMotions) {
    const double T = 2.0;
    const RefState ref = free_reference(c.I, c.w0, T, 200000);
    for (double h : {1e-3, 0.02, 0.25}) {
      const RotorRun r = run_cached(c, h, std::lround(T / h));
      const Vec3 m_ref = c.I.cwiseProduct(to_double(ref.w));
      EXPECT_LT(angle_between(r.q, to_double(ref.q)), 2e-12) << c.I.transpose() << " h=" << h;
      EXPECT_LT((r.m - m_ref).norm(), 2e-12 * m_ref.norm()) << c.I.transpose() << " h=" << h;
    }
  }
}

// The tennis-racket flip near the separatrix, over 20 s: the case whose flip timing is most
// sensitive to the invariants. Exact to round-off at every step length, long steps included.
TEST(FreeRotor, RacketFlipIsStepSizeIndependent) {
  const Motion c{{1, 2, 3}, {1e-3, 5.0, 1e-3}};
  const RefState ref = free_reference(c.I, c.w0, 20.0, 2000000);
  for (double h : {1e-4, 1e-3, 1.0 / 60, 0.5, 4.0}) {
    const RotorRun r = run_cached(c, h, std::lround(20.0 / h));
    EXPECT_LT(angle_between(r.q, to_double(ref.q)), 1e-12) << "h=" << h;
  }
}

// Closer still to the separatrix (w0 = (1e-6, 5, 1e-6)): the motion amplifies round-off about
// 1e12-fold, beyond what a long-double reference can resolve, so the oracle here is the Taylor
// series in quad precision. Exact to round-off still, at every step length.
TEST(FreeRotor, NearSeparatrixAgainstAQuadPrecisionOracle) {
  const double I[3] = {1, 2, 3}, w0[3] = {1e-6, 5, 1e-6};
  long double q[4], w[3];
  taylor_free_run(I, w0, 20.0, 4000, 24, q, w);
  const Quat ref = Quat(double(q[0]), double(q[1]), double(q[2]), double(q[3])).normalized();
  for (double h : {1e-3, 1.0 / 60, 0.5}) {
    const RotorRun r = run_cached({{1, 2, 3}, {1e-6, 5.0, 1e-6}}, h, std::lround(20.0 / h));
    // 1e-12: round-off amplified by the motion's own conditioning (the same initial state moved
    // by one ulp ends ~1e-13 away); a 0.5 s step evaluates F(phi|m) and sn at |u| ~ 40.
    EXPECT_LT(angle_between(r.q, ref), h < 0.1 ? 1e-12 : 3e-12) << "h=" << h;
  }
}

// A long step's psi in closed form (Carlson R_F, R_J) against the same step by Gauss-Legendre
// panels, from phases all round the period (both quadrants of cn, so both reductions of the start
// amplitude), for phase advances from just past the short-step limit to hundreds of periods, in
// both cases of the motion, both update modes, and q = rho / r from 5e-7 to 60.
TEST(FreeRotor, LongStepsInClosedFormAgreeWithThePanels) {
  const Motion motions[] = {
      {{1, 2, 3}, {0.3, 0.1, 2.0}},          {{1, 2, 3}, {1.5, 0.2, 0.3}},
      {{1, 2, 3}, {1e-3, 5.0, 1e-3}},        {{0.5, 1.3, 1.7}, {20.0, 0.5, 20.0}},
      {{1e-3, 1.0, 1.0005}, {50, 1, 0.2}},   {{1.0, 1.9, 1.92}, {0.7, 0.4, 2.0}},
      {{1.0, 1.02, 2.0}, {0.01, 3.0, 0.05}}, {{2, 2.5, 4}, {-1.0, 3.0, -2.0}},
  };
  int closed = 0;
  for (const Motion& c : motions) {
    const RotorInertia J(c.I);
    for (double h : {0.03, 0.11, 0.5, 3.0, 40.0}) {
      Vec3 m = c.I.cwiseProduct(c.w0);
      // Walk the start phase round the period with short exact steps between the comparisons.
      RotorPlan walk;
      physics::make_rotor_plan(J, m, 0.37, walk);
      for (int k = 0; k < 12; ++k) {
        RotorPlan p;
        physics::make_rotor_plan(J, m, h, p);
        if (p.n != 0) continue;  // a short step: no long path to compare
        closed += p.closed;
        RotorPlan panels = p;
        panels.closed = false;
        for (auto update : {physics::RotorUpdate::kPinned, physics::RotorUpdate::kIncrement}) {
          Vec3 m1 = m, m2 = m;
          Quat d1, d2;
          physics::advance_rotor(p, m1, d1, update);
          physics::advance_rotor(panels, m2, d2, update);
          // Near the separatrix the start phase's inversion is ill-conditioned (dF/dphi = 1 /
          // Delta up to 1 / k'), and the two paths invert differently: the bound grows with
          // 1 / k'. Those motions are checked against oracles by the tests above.
          const double tol = 3e-14 * std::max(1.0, std::abs(p.X)) / std::sqrt(p.mc);
          EXPECT_LT(angle_between(d1, d2), tol) << c.I.transpose() << " h=" << h << " X=" << p.X;
          // The same end phase but for the start phase's inversion (atan2 and F against F alone).
          EXPECT_LT((m1 - m2).norm(), tol * m.norm()) << c.I.transpose() << " h=" << h;
        }
        Quat dq;
        physics::advance_rotor(walk, m, dq);
      }
    }
  }
  EXPECT_GT(closed, 200);  // the closed form did run
}

TEST(FreeRotor, ConservesAngularMomentumAndEnergyToRoundOff) {
  for (const Motion& c : kMotions) {
    const Vec3 m0 = c.I.cwiseProduct(c.w0);
    const Vec3 L0 = m0;  // q starts at identity
    const double E0 = 0.5 * m0.dot(c.I.cwiseInverse().cwiseProduct(m0));
    const RotorRun r = run_cached(c, 1e-3, 20000);
    const Vec3 L = r.q * r.m;
    const double E = 0.5 * r.m.dot(c.I.cwiseInverse().cwiseProduct(r.m));
    EXPECT_LT((L - L0).norm(), 1e-12 * L0.norm()) << c.I.transpose();  // 2e4 steps of round-off
    EXPECT_LT(std::abs(E - E0), 1e-12 * E0) << c.I.transpose();
  }
}

TEST(FreeRotor, PureSpinsStayPure) {
  const Vec3 I(1, 2, 3);
  for (int axis = 0; axis < 3; ++axis) {
    const Vec3 w0 = 4.0 * Vec3::Unit(axis);
    const RotorRun r = run_cached({I, w0}, 0.01, 300);
    const Quat expect(Eigen::AngleAxisd(4.0 * 3.0, Vec3::Unit(axis)));
    EXPECT_LT(angle_between(r.q, expect), 1e-13) << axis;  // even the unstable middle axis
    EXPECT_LT((r.m - I.cwiseProduct(w0)).norm(), 1e-13) << axis;
  }
  RotorRun still = run_cached({I, Vec3::Zero()}, 0.01, 10);
  EXPECT_EQ(still.q.coeffs(), Quat::Identity().coeffs());
  EXPECT_EQ(still.m, Vec3::Zero());
}

TEST(FreeRotor, AxisymmetricPrecessionMatchesTheReference) {
  for (const Motion& c : {Motion{{1, 1, 3}, {2, -1, 5}}, Motion{{3, 3, 1}, {0.5, 2, -4}},
                          Motion{{1, 1, 1e-4}, {1, 0.2, 50}}}) {
    const double T = 2.0, h = 1e-3;
    const RefState ref = free_reference(c.I, c.w0, T, 200000);
    Vec3 m = c.I.cwiseProduct(c.w0);
    Quat q = Quat::Identity();
    AxisymPlan p;
    physics::make_axisym_plan(c.I.x(), c.I.z(), m, h, p);
    for (long i = 0; i < std::lround(T / h); ++i) {
      Quat dq;
      physics::advance_axisym(p, m, dq);
      q = q * dq;
      physics::renormalize(q);
    }
    EXPECT_LT(angle_between(q, to_double(ref.q)), 1e-12) << c.I.transpose();
    EXPECT_LT((m - c.I.cwiseProduct(to_double(ref.w))).norm(), 1e-12 * m.norm());
  }
}

}  // namespace
}  // namespace rigid::test
