// rigid-view's drift of energy and angular momentum (drift.hpp): the formulas on a case worked
// by hand, and the tracker's references (first state, reset, new scene, a driven body).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "drift.hpp"

namespace {

using namespace rigid;
using namespace rigid::view;

TEST(ViewDrift, InvariantsOnACaseWorkedByHand) {
  // I_B = diag(1, 2, 3), m = 2, q_WB a quarter turn about x (R maps (x, y, z) to (x, -z, y)),
  // w_B = (0.1, 2, 0.3), so w_W = R w_B = (0.1, -0.3, 2); v = (1, 0, 0), p = (0, 0, 1),
  // g = (0, 0, -9.81). E = 1/2 m v.v + 1/2 w_B.I w_B - m g.p and L_W = R I w_B = R (0.1, 4, 0.9)
  // = (0.1, -0.9, 4). The quaternion is given unnormalised (x 3): invariants() normalises it.
  const double I[6] = {1, 2, 3, 0, 0, 0};
  const double p[3] = {0, 0, 1}, v[3] = {1, 0, 0}, w[3] = {0.1, -0.3, 2};
  const double q[4] = {3 * std::sqrt(0.5), 3 * std::sqrt(0.5), 0, 0};
  const Invariants got = invariants(2, I, Vec3{0, 0, -9.81}, p, q, v, w);
  const double e = 0.5 * 2 * 1 + 0.5 * (1 * 0.1 * 0.1 + 2 * 2 * 2 + 3 * 0.3 * 0.3) + 2 * 9.81 * 1;
  EXPECT_NEAR(got.energy, e, 1e-12);
  EXPECT_NEAR(got.L_W[0], 0.1, 1e-12);
  EXPECT_NEAR(got.L_W[1], -0.9, 1e-12);
  EXPECT_NEAR(got.L_W[2], 4, 1e-12);
  // Products of inertia count: I_xy = 0.5 adds I_xy w_y to L_x and I_xy w_x to L_y (in B).
  const double J[6] = {1, 2, 3, 0.5, 0, 0};
  const double one[4] = {1, 0, 0, 0}, spin[3] = {1, 2, 0}, zero[3] = {0, 0, 0};
  const Invariants c = invariants(1, J, Vec3{0, 0, 0}, zero, one, zero, spin);
  EXPECT_NEAR(c.L_W[0], 1 + 0.5 * 2, 1e-15);
  EXPECT_NEAR(c.L_W[1], 2 * 2 + 0.5 * 1, 1e-15);
  EXPECT_NEAR(c.energy, 0.5 * (1 * c.L_W[0] + 2 * c.L_W[1]), 1e-15);
}

SceneDescription three_bodies(double dt) {
  SceneDescription d;
  d.dt = dt;
  d.ids = {10, 20, 30};
  d.names = {"a", "b", "c"};
  d.masses = {1, 2, 3};
  d.inertia = {1, 1, 1, 0, 0, 0, 1, 2, 3, 0, 0, 0, 2, 2, 2, 0, 0, 0};
  d.shape_kinds.assign(3, ShapeKind{});
  d.shape_dims.assign(9, 0.0);
  return d;
}

// The bodies of three_bodies in the order `ids`, at rest except that body 20 (if present)
// moves at speed `v` along x and body 30 spins at `spin` about z.
StateFrame state(std::int64_t tick, std::vector<std::int32_t> ids, double v, double spin = 1) {
  StateFrame s;
  s.resize(ids.size());
  s.tick = tick;
  s.ids = ids;
  for (std::size_t i = 0; i < ids.size(); ++i) {
    s.orientation[4 * i] = 1;
    if (ids[i] == 20) s.linear_velocity[3 * i] = v;
    if (ids[i] == 30) s.angular_velocity[3 * i + 2] = spin;
  }
  return s;
}

TEST(ViewDrift, RelativeToEachBodysFirstStateInTheStatesOrder) {
  DriftTracker t;
  t.set_scene(three_bodies(0.01));
  t.update(state(0, {30, 10, 20}, 1));
  ASSERT_EQ(t.energy().size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(t.energy()[i], 0.0f);
    EXPECT_EQ(t.momentum()[i], 0.0f);
  }
  // Body 20 twice as fast: its energy x4 (relative drift 3), its angular momentum still 0. Body
  // 30 spins 1.5x: energy x2.25, |L| x1.5. An id the scene does not have: 0. Another order.
  t.update(state(1, {20, 99, 30, 10}, 2, 1.5));
  ASSERT_EQ(t.energy().size(), 4u);
  EXPECT_FLOAT_EQ(t.energy()[0], 3.0f);
  EXPECT_EQ(t.momentum()[0], 0.0f);
  EXPECT_EQ(t.energy()[1], 0.0f);
  EXPECT_FLOAT_EQ(t.energy()[2], 1.25f);
  EXPECT_FLOAT_EQ(t.momentum()[2], 0.5f);
  EXPECT_EQ(t.energy()[3], 0.0f);
  // A quantity that starts at zero is compared to 1: body 20's L_W = 0 at first; now a spin.
  StateFrame s = state(2, {20}, 1);
  s.angular_velocity[0] = 0.25;  // I_xx = 1 (body 20's inertia is diag(1, 2, 3))
  t.update(s);
  EXPECT_FLOAT_EQ(t.momentum()[0], 0.25f);
}

TEST(ViewDrift, AResetOrANewSceneTakesEveryReferenceAgain) {
  DriftTracker t;
  t.set_scene(three_bodies(0.01));
  t.update(state(5, {10, 20, 30}, 1));
  t.update(state(6, {10, 20, 30}, 3));
  EXPECT_FLOAT_EQ(t.energy()[1], 8.0f);
  t.update(state(2, {10, 20, 30}, 3));  // the tick went back: rigidd was reset
  EXPECT_EQ(t.energy()[1], 0.0f);
  t.update(state(3, {10, 20, 30}, 6));
  EXPECT_FLOAT_EQ(t.energy()[1], 3.0f);
  t.set_scene(three_bodies(0.01));
  t.update(state(4, {10, 20, 30}, 1));
  EXPECT_EQ(t.energy()[1], 0.0f);
}

TEST(ViewDrift, ADrivenBodysReferenceFollowsItUntilTheMarginAfterItsWrench) {
  // dt = 10 ms: kDrivenMargin (0.25 s) is 25 ticks. A wrench accepted at tick 10 for 0.05 s (5
  // ticks) acts on the states 11..15; body 20's reference is taken again with every state up to
  // tick 40.
  DriftTracker t;
  t.set_scene(three_bodies(0.01));
  ASSERT_EQ(DriftTracker::kDrivenMargin, 0.25);
  t.update(state(10, {10, 20, 30}, 1));
  t.drive(20, 10, 0.05);
  t.drive(99, 10, 0.05);  // an id the scene does not have: nothing
  double v = 1;
  for (std::int64_t tick = 11; tick <= 40; ++tick) {
    v += 0.5;
    t.update(state(tick, {10, 20, 30}, v, 1 + 1e-3 * static_cast<double>(tick)));
    EXPECT_EQ(t.energy()[1], 0.0f) << tick;
    EXPECT_GT(t.energy()[2], 0.0f) << tick;  // body 30 is not driven: its change is drift
  }
  // Tick 41: measured from the state at tick 40 (speed v), no more retaken.
  t.update(state(41, {10, 20, 30}, 2 * v));
  EXPECT_FLOAT_EQ(t.energy()[1], 3.0f);
  t.update(state(42, {10, 20, 30}, v));
  EXPECT_EQ(t.energy()[1], 0.0f);
  // A wrench whose ttl gives no sensible tick count (too long for rigidd's table) drives its
  // body until the next reset.
  t.drive(10, 42, 1e300);
  StateFrame far = state(100000, {10}, 0);
  far.linear_velocity[0] = 5;
  t.update(far);
  EXPECT_EQ(t.energy()[0], 0.0f);
  t.update(state(1, {10}, 0));  // reset
  far.tick = 2;
  t.update(far);
  EXPECT_GT(t.energy()[0], 1.0f);
}

}  // namespace
