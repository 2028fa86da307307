// Physics faults seen through the loop: a body whose scheme diverges under a command is frozen by
// the world's guard, the loop reports it once for the log and counts it in its summary (what Stats
// carries), and the rest of the world goes on exactly as before; large rotations are counted too.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>

#include "loop/loop.hpp"
#include "loop_harness.hpp"

namespace rigid::loop {
namespace {

using namespace std::chrono_literals;
using rigid::ControlKind;
using rigid::Mode;
using rigid::Outcome;
using testing::Harness;
using testing::make_scene;

// RK4 at 1 kHz. The sled's drag is stiff for RK4 (c dt / m = 5: x13.7 per step once it moves)
// but harmless at rest; the puck is a witness; the ball spins past pi per tick under a torque.
const char* kDivergingScene = R"(
world { rate_hz: 1000 publish_every: 1 gravity { z: 0 } integrator: "rk4"
        limits { max_force: 1e6 max_torque: 1e6 max_ttl: 10 } }
body { name: "puck" mass: 2 }
body { name: "sled" mass: 1 linear_drag: 5000 }
body { name: "ball" mass: 1 inertia { x: 1 y: 1 z: 1 } }
)";
constexpr int kPuck = 0;
constexpr int kSled = 1;
constexpr int kBall = 2;

Wrench force_on(std::int32_t body, std::int64_t seq, double fx, double ttl) {
  Wrench w;
  w.source = 1;
  w.seq = seq;
  w.body = body;
  w.force = {fx, 0, 0};
  w.ttl = ttl;
  return w;
}

// Waits for a summary that satisfies pred (the loop rolls one a second, idle or not).
template <class Pred>
bool wait_summary(Loop& loop, LoopSummary& s, Pred pred) {
  const auto deadline = std::chrono::steady_clock::now() + 5s;
  while (std::chrono::steady_clock::now() < deadline) {
    if (loop.take_summary(s) && pred(s)) return true;
    std::this_thread::sleep_for(10ms);
  }
  return false;
}

TEST(LoopPhysicsFault, ADivergingBodyIsFrozenReportedOnceAndTheRestGoesOn) {
  Harness h(make_scene(kDivergingScene), Mode::kLockstep);
  h.start();
  std::int64_t seq = 0;
  // 1 N on the sled for one tick sets it moving; RK4 then multiplies its velocity by -13.7 a step
  // and it passes 1e100 within ~90 ticks: the guard (each body every 64 steps, the sled after
  // ticks 43, 107, ...: World::guard_phase) catches it by tick 128.
  h.wrench(force_on(kSled, ++seq, 1.0, 0.0));
  // 4 N on the 2 kg puck for the whole run: +0.002 m/s per tick, whatever the sled does.
  h.wrench(force_on(kPuck, ++seq, 4.0, 1.0));
  // 1e6 N m on the unit-inertia ball for 4 ticks: ~4000 rad/s, more than pi per 1 ms tick.
  Wrench spin;
  spin.source = 1;
  spin.seq = ++seq;
  spin.body = kBall;
  spin.torque = {0, 0, 1e6};
  spin.ttl = 0.004;
  h.wrench(spin);
  h.control(ControlKind::kStep, ++seq, 300);
  ASSERT_EQ(h.reply_to(seq).outcome, Outcome::kOk);

  const rigid::StateFrame s = h.last_state();
  ASSERT_EQ(s.tick, 300);
  // The sled: held at its last good state, at rest, finite.
  EXPECT_EQ(s.linear_velocity[3 * kSled], 0.0);
  EXPECT_TRUE(std::isfinite(s.position[3 * kSled]));
  EXPECT_LE(std::abs(s.position[3 * kSled]), 1e100);
  // The puck: exactly 300 ticks' worth of 2 m/s^2.
  EXPECT_NEAR(s.linear_velocity[3 * kPuck], 0.6, 1e-12);
  // The ball spins on, finite.
  EXPECT_GT(s.angular_velocity[3 * kBall + 2], 3200.0);
  EXPECT_TRUE(std::isfinite(s.orientation[4 * kBall]));

  FrozenBody f;
  ASSERT_TRUE(h.loop().take_frozen(f));
  EXPECT_EQ(f.body, kSled);
  EXPECT_GT(f.tick, 1);
  EXPECT_LE(f.tick, 128);
  EXPECT_EQ(f.tick % physics::World::kGuardEvery, h.loop().world().guard_phase(kSled));
  EXPECT_FALSE(h.loop().take_frozen(f));  // once

  LoopSummary summary;
  ASSERT_TRUE(wait_summary(h.loop(), summary, [](const LoopSummary& x) { return x.tick == 300; }));
  EXPECT_EQ(summary.bodies_frozen, 1);
  // The ball turns by more than pi in each of its ~296 ticks after the spin-up.
  EXPECT_GE(summary.large_rotation_steps, 290);
  EXPECT_LE(summary.large_rotation_steps, 300);
  const std::int64_t large_before_reset = summary.large_rotation_steps;

  // A reset thaws the sled; pushed again it diverges again and is frozen again, but the log has
  // had its line: no second report. Large rotations are counted since start, across the reset.
  h.control(ControlKind::kReset, ++seq);
  ASSERT_EQ(h.reply_to(seq).outcome, Outcome::kOk);
  h.wrench(force_on(kSled, ++seq, 1.0, 0.0));
  spin.seq = ++seq;
  h.wrench(spin);
  h.control(ControlKind::kStep, ++seq, 200);
  ASSERT_EQ(h.reply_to(seq).outcome, Outcome::kOk);
  EXPECT_EQ(h.last_state().linear_velocity[3 * kSled], 0.0);
  EXPECT_FALSE(h.loop().take_frozen(f));
  ASSERT_TRUE(wait_summary(h.loop(), summary, [](const LoopSummary& x) { return x.tick == 200; }));
  EXPECT_EQ(summary.bodies_frozen, 1);
  EXPECT_GE(summary.large_rotation_steps, large_before_reset + 190);
}

TEST(LoopPhysicsFault, AResetThawsAndTheSummaryCountsNoFrozenBody) {
  Harness h(make_scene(kDivergingScene), Mode::kLockstep);
  h.start();
  h.wrench(force_on(kSled, 1, 1.0, 0.0));
  h.control(ControlKind::kStep, 2, 200);
  ASSERT_EQ(h.reply_to(2).outcome, Outcome::kOk);
  h.control(ControlKind::kReset, 3);
  ASSERT_EQ(h.reply_to(3).outcome, Outcome::kOk);
  LoopSummary summary;
  // The first summary after the reset: nothing frozen, nothing turned fast.
  ASSERT_TRUE(wait_summary(h.loop(), summary, [](const LoopSummary& x) { return x.tick == 0; }));
  EXPECT_EQ(summary.bodies_frozen, 0);
  EXPECT_EQ(summary.large_rotation_steps, 0);
  FrozenBody f;
  EXPECT_TRUE(h.loop().take_frozen(f));  // it was frozen before the reset: reported
  EXPECT_EQ(f.body, kSled);
}

}  // namespace
}  // namespace rigid::loop
