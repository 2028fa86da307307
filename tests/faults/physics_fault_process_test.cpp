// A physics fault in a real rigidd, on each bus: a push within the scene's limits makes a body's
// integration diverge (tests/faults/scenes/diverging.pbtxt: RK4 on a stiff drag); the world's guard
// freezes that body, rigidd logs it once by name, Stats (and rigidctl stats) count it with the
// large-rotation steps of a body spun past pi per tick, and the rest of the world goes on exactly.
#include <gtest/gtest.h>

#include <charconv>
#include <cmath>
#include <string>

#include "fault_rig.hpp"
#include "physics/world.hpp"
#include "scene/scene.hpp"

namespace rigid::faults::testing {
namespace {

const std::string kDiverging = std::string(RIGID_FAULT_SCENES) + "/diverging.pbtxt";
constexpr int kPuck = 0;
constexpr int kSled = 1;
constexpr int kBall = 2;

class PhysicsFault : public ::testing::TestWithParam<Bus> {};

TEST_P(PhysicsFault, ADivergingBodyIsFrozenLoggedOnceAndCountedWhileTheRestGoesOn) {
  Rig rig(GetParam(), kDiverging);
  ASSERT_TRUE(rig.handshake()) << rig.daemon->stderr_text();
  rigid::WrenchCommand w;
  w.body_id = kSled;  // 1 N for one tick: RK4 then multiplies its velocity by -13.7 a tick
  w.force = {1, 0, 0};
  rig.monitor->send(w);
  w.body_id = kPuck;  // 4 N on 2 kg for 3 s: +0.002 m/s a tick
  w.force = {4, 0, 0};
  w.ttl = 3.0;
  rig.monitor->send(w);
  w = {};
  w.body_id = kBall;  // 1e6 N m for 4 ticks on a unit inertia: ~4000 rad/s, > pi per tick
  w.torque = {0, 0, 1e6};
  w.ttl = 0.004;
  rig.monitor->send(w);

  ASSERT_TRUE(rig.monitor->wait(
      [&] {
        const auto& s = rig.monitor->stats_locked();
        return s && s->bodies_frozen == 1 && s->large_rotation_steps > 100;
      },
      5s))
      << "Stats never counted the frozen sled; rigidd:\n"
      << rig.daemon->stderr_text();

  // One line, naming the body, at a tick where the guard looks at it (every 64 steps, at its
  // phase: World::guard_phase).
  const std::string key = "rigidd: body 'sled' (id 1) frozen at tick ";
  std::string err;
  ASSERT_TRUE(poll_until(
      [&] {
        err = rig.daemon->stderr_text();
        return err.find(key) != std::string::npos;
      },
      2s))
      << err;
  const auto at = err.find(key);
  EXPECT_EQ(err.find(key, at + 1), std::string::npos) << "logged twice:\n" << err;
  std::int64_t frozen_tick = -1;
  std::from_chars(err.data() + at + key.size(), err.data() + err.size(), frozen_tick);
  const physics::World world(scene::load_scene(kDiverging).world);
  EXPECT_EQ(frozen_tick % physics::World::kGuardEvery, world.guard_phase(kSled)) << err;
  EXPECT_NE(err.find("the rest of the world goes on", at), std::string::npos) << err;

  // After the freeze: the sled at rest and finite, the puck pushed exactly as if alone, the ball
  // spinning on.
  const std::vector<rigidd::testing::TimedState> states = rig.monitor->states();
  // The first tick the puck moved, read off the first moving frame's velocity (k ticks pushed =
  // k * 0.002 m/s): state is best-effort keep-last-1, so that frame's own tick may be a later one.
  std::int64_t onset = -1;
  int checked = 0;
  for (const auto& t : states) {
    const rigid::StateFrame& s = t.state;
    if (onset < 0 && s.linear_velocity[3 * kPuck] > 0)
      onset = s.tick + 1 - std::llround(s.linear_velocity[3 * kPuck] / 0.002);
    if (onset < 0 || s.tick < frozen_tick) continue;
    EXPECT_EQ(s.linear_velocity[3 * kSled], 0.0) << "tick " << s.tick;
    EXPECT_TRUE(std::isfinite(s.position[3 * kSled])) << "tick " << s.tick;
    EXPECT_NEAR(s.linear_velocity[3 * kPuck],
                0.002 * static_cast<double>(std::min<std::int64_t>(s.tick - onset + 1, 3000)),
                1e-11)
        << "tick " << s.tick;
    EXPECT_GT(std::abs(s.angular_velocity[3 * kBall + 2]), 3141.6) << "tick " << s.tick;
    ++checked;
  }
  EXPECT_GT(checked, 100);

  const Completed stats = rig.run(RIGIDCTL_EXE, {"stats", "--once"});
  EXPECT_EQ(stats.exit_code, 0) << stats.err;
  EXPECT_NE(stats.out.find("physics: bodies frozen 1, large-rotation steps "), std::string::npos)
      << stats.out;
  EXPECT_EQ(rig.daemon->terminate(1000ms), 0);
  EXPECT_NE(rig.daemon->stderr_text().find(" bodies_frozen=1"), std::string::npos)
      << rig.daemon->stderr_text();
}

INSTANTIATE_TEST_SUITE_P(Bus, PhysicsFault, ::testing::Values(Bus::kDds, Bus::kLcm), param_name);

}  // namespace
}  // namespace rigid::faults::testing
