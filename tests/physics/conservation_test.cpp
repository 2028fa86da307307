// A torque-free body whose principal moments all differ keeps its world angular momentum and its
// energy: exactly (to round-off) for the exact-rotor splittings, L exactly and E bounded for DLM's
// splitting, to O(h^4) for RK4; the implicit gyroscopic step drains energy, as it is known to.
#include <gtest/gtest.h>

#include "test_util.hpp"

namespace rigid::test {
namespace {

struct Drift {
  double L = 0, E = 0;             // largest relative error along the run
  double E_first = 0, E_last = 0;  // largest relative energy error in the first / last tenth
  double E_end = 0;                // signed relative energy change at the end
};

Drift run(const std::string& integrator, double h, long n) {
  World w(one_body(body("b", {1, 2, 3}, {1.0, 2.0, 3.0}), h, integrator));
  const Vec3 L0 = w.angular_momentum_W(0);
  const double E0 = w.kinetic_energy(0);
  Drift d;
  for (long i = 1; i <= n; ++i) {
    w.step();
    const double eL = (w.angular_momentum_W(0) - L0).norm() / L0.norm();
    const double eE = std::abs(w.kinetic_energy(0) - E0) / E0;
    d.L = std::max(d.L, eL);
    d.E = std::max(d.E, eE);
    if (i <= n / 10) d.E_first = std::max(d.E_first, eE);
    if (i > n - n / 10) d.E_last = std::max(d.E_last, eE);
  }
  d.E_end = (w.kinetic_energy(0) - E0) / E0;
  return d;
}

// Round-off only: 10^5 steps of it random-walk to a few 1e-13.
TEST(Conservation, ExactRotorSplittingsConserveBothToRoundOff) {
  for (const std::string name : {"exact_rotor4", "exact_rotor"}) {
    const Drift d = run(name, 0.01, 100000);
    EXPECT_LT(d.L, 1e-12) << name;
    EXPECT_LT(d.E, 1e-12) << name;
  }
}

TEST(Conservation, DlmConservesAngularMomentumExactlyAndBoundsEnergy) {
  const Drift d = run("dlm", 0.01, 100000);
  EXPECT_LT(d.L, 1e-11);  // exact rotations; five rounded sin/cos pairs a step accumulate
  EXPECT_LT(d.E, 1e-3);
  // Symplectic: the energy error oscillates, it does not grow.
  EXPECT_LT(d.E_last, 2.0 * d.E_first);
}

TEST(Conservation, Rk4ConservesToItsOrder) {
  const Drift coarse = run("rk4", 0.02, 500), fine = run("rk4", 0.01, 1000);
  EXPECT_LT(coarse.E, 2e-6);  // h |w| = 0.075
  EXPECT_LT(coarse.L, 2e-6);
  // Fourth order: halving the step divides the error by about 16 (and by at least 8).
  EXPECT_GT(coarse.E / fine.E, 8.0);
}

TEST(Conservation, ImplicitGyroscopicStepDrainsEnergy) {
  const Drift d = run("implicit_gyro", 0.01, 1000);
  EXPECT_LT(d.E_end, -1e-3);  // loses energy: the documented damping of backward Euler
}

}  // namespace
}  // namespace rigid::test
