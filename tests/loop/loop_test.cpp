// The loop's behaviour with an in-memory output: lockstep stepping, control requests and their
// answers, wrenches (replace by key, time to live, stale sequence numbers) acting on the world
// exactly as World::add_force would, publishing cadence, pause/resume/reset in realtime.
#include "loop/loop.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>
#include <utility>

#include "loop/clock.hpp"
#include "loop_harness.hpp"

namespace rigid::loop {
namespace {

using namespace std::chrono_literals;
using rigid::ControlKind;
using rigid::Mode;
using rigid::Outcome;
using testing::Harness;
using testing::make_scene;

// A point mass of 2 kg and a general body at rest, no gravity, 1 kHz, a state every 10 ticks.
const char* kScene = R"(
world { rate_hz: 1000 publish_every: 10 gravity { z: 0 } limits { max_ttl: 10 } }
body { name: "puck" mass: 2 }
body { name: "brick" mass: 1 inertia { x: 1 y: 2 z: 3 } orientation { w: 0.7071067811865476 z: 0.7071067811865476 } }
)";

Wrench push_puck(std::int64_t seq, double fx, double ttl, std::int32_t key = 0) {
  Wrench w;
  w.source = 1;
  w.seq = seq;
  w.key = key;
  w.body = 0;
  w.force = {fx, 0, 0};
  w.ttl = ttl;
  return w;
}

TEST(Loop, LockstepAdvancesExactlyTheTicksRequested) {
  Harness h(make_scene(kScene), Mode::kLockstep);
  h.start();
  ASSERT_TRUE(h.wait([&] { return h.out.states >= 1; }));  // tick 0 is published at start
  EXPECT_EQ(h.last_state().tick, 0);
  std::this_thread::sleep_for(50ms);
  EXPECT_EQ(h.loop().heartbeat() > 0, true);
  EXPECT_EQ(h.last_state().tick, 0);  // nothing moves without a step

  h.control(ControlKind::kStep, 1, 7);
  const Reply r = h.reply_to(1);
  EXPECT_EQ(r.outcome, Outcome::kOk);
  EXPECT_EQ(r.tick, 7);
  EXPECT_EQ(h.last_state().tick, 7);  // the final tick's state is published before the reply
  h.control(ControlKind::kStep, 2, 3);
  EXPECT_EQ(h.reply_to(2).tick, 10);
  EXPECT_NEAR(h.last_state().sim_time, 0.010, 1e-15);
  h.stop();
  EXPECT_EQ(h.loop().tick(), 10);
  EXPECT_EQ(h.loop().world().step_count(), 10);
}

TEST(Loop, LockstepRefusesPauseResumeAndRtf) {
  Harness h(make_scene(kScene), Mode::kLockstep);
  h.start();
  h.control(ControlKind::kPause, 1);
  h.control(ControlKind::kResume, 2);
  h.control(ControlKind::kSetRtf, 3, 0, 2.0);
  EXPECT_EQ(h.reply_to(1).outcome, Outcome::kNotAllowed);
  EXPECT_EQ(h.reply_to(2).outcome, Outcome::kNotAllowed);
  EXPECT_EQ(h.reply_to(3).outcome, Outcome::kNotAllowed);
  EXPECT_EQ(h.reply_to(3).note, ReplyNote::kRtfNeedsRealtime);
}

TEST(Loop, AWrenchActsForItsTimeToLiveThenStops) {
  Harness h(make_scene(kScene), Mode::kLockstep);
  h.start();
  // 4 N on 2 kg for 5 ticks of 1 ms: dv = 2 m/s^2 * 5 ms = 0.01 m/s.
  h.wrench(push_puck(1, 4.0, 0.005));
  h.control(ControlKind::kStep, 1, 20);
  ASSERT_EQ(h.reply_to(1).outcome, Outcome::kOk);
  EXPECT_NEAR(h.last_state().linear_velocity[0], 0.01, 1e-15);
  // ttl 0: exactly one tick.
  h.wrench(push_puck(2, 4.0, 0.0));
  h.control(ControlKind::kStep, 2, 20);
  ASSERT_EQ(h.reply_to(2).outcome, Outcome::kOk);
  EXPECT_NEAR(h.last_state().linear_velocity[0], 0.012, 1e-15);
}

TEST(Loop, TheSameKeyReplacesAndOtherKeysAdd) {
  Harness h(make_scene(kScene), Mode::kLockstep);
  h.start();
  h.wrench(push_puck(1, 2.0, 1.0));
  h.wrench(push_puck(2, 4.0, 1.0));             // same key: replaces the 2 N
  h.wrench(push_puck(3, 1.0, 1.0, /*key=*/1));  // another key: adds
  h.control(ControlKind::kStep, 1, 10);
  ASSERT_EQ(h.reply_to(1).outcome, Outcome::kOk);
  // (4 + 1) N / 2 kg * 10 ms
  EXPECT_NEAR(h.last_state().linear_velocity[0], 0.025, 1e-15);
  EXPECT_EQ(h.loop().commands_accepted(), 4);
}

TEST(Loop, StaleSequenceNumbersAreRefusedAndNeverReachTheWorld) {
  Harness h(make_scene(kScene), Mode::kLockstep);
  h.start();
  h.wrench(push_puck(5, 2.0, 1.0));
  h.wrench(push_puck(5, 100.0, 1.0));  // repeated
  h.wrench(push_puck(3, 100.0, 1.0));  // backwards
  h.control(ControlKind::kStep, 9, 10);
  h.control(ControlKind::kStep, 8, 10);  // backwards control: answered invalid
  ASSERT_EQ(h.reply_to(9).outcome, Outcome::kOk);
  const Reply stale = h.reply_to(8);
  EXPECT_EQ(stale.outcome, Outcome::kInvalid);
  EXPECT_EQ(stale.note, ReplyNote::kStaleSequence);
  EXPECT_EQ(reply_message(stale), "stale sequence number (the source's last one is 9)");
  EXPECT_NEAR(h.last_state().linear_velocity[0], 0.01, 1e-15);
  EXPECT_EQ(h.rejects().counts().stale_sequence, 3);
}

TEST(Loop, BodyForceAtALeverArmMatchesTheWorldDirectly) {
  // The loop must hand the wrench to the physics unchanged (frames included): compare with a
  // World driven by hand.
  const scene::Scene s = make_scene(kScene);
  Harness h(s, Mode::kLockstep);
  h.start();
  Wrench w;
  w.source = 3;
  w.seq = 1;
  w.body = 1;
  w.force = {0, 0, 2};
  w.point = {0.5, 0, 0};
  w.force_frame = rigid::Frame::kBody;
  w.torque = {0.1, 0, 0};
  w.torque_frame = rigid::Frame::kWorld;
  w.ttl = 1.0;
  h.wrench(w);
  h.control(ControlKind::kStep, 1, 25);
  ASSERT_EQ(h.reply_to(1).outcome, Outcome::kOk);

  physics::World ref(s.world);
  for (int i = 0; i < 25; ++i) {
    ref.clear_applied();
    ref.add_force(1, {0, 0, 2}, {0.5, 0, 0}, physics::Frame::kBody);
    ref.add_torque(1, {0.1, 0, 0}, physics::Frame::kWorld);
    ref.step();
  }
  const physics::BodyState b = ref.state(1);
  const rigid::StateFrame f = h.last_state();
  EXPECT_EQ(f.angular_velocity[3], b.w_WB.x());
  EXPECT_EQ(f.angular_velocity[4], b.w_WB.y());
  EXPECT_EQ(f.angular_velocity[5], b.w_WB.z());
  EXPECT_EQ(f.orientation[4], b.q_WB.w());
  EXPECT_EQ(f.linear_velocity[5], b.v_WBo.z());
}

TEST(Loop, AStepWhileAnotherRunsIsRefusedAndResetInterruptsIt) {
  Harness h(make_scene(kScene), Mode::kLockstep);
  h.start();
  h.control(ControlKind::kStep, 1, 1'000'000'000);
  h.control(ControlKind::kStep, 2, 5);
  const Reply busy = h.reply_to(2);
  EXPECT_EQ(busy.outcome, Outcome::kNotAllowed);
  EXPECT_EQ(busy.note, ReplyNote::kStepInProgress);
  h.control(ControlKind::kReset, 3);
  const Reply cut = h.reply_to(1);
  EXPECT_EQ(cut.outcome, Outcome::kFailed);
  EXPECT_EQ(cut.note, ReplyNote::kInterruptedByReset);
  EXPECT_EQ(h.reply_to(3).outcome, Outcome::kOk);
  EXPECT_EQ(h.reply_to(3).tick, 0);
  EXPECT_EQ(h.last_state().tick, 0);
}

TEST(Loop, RealtimePauseStepResumeReset) {
  Harness h(make_scene(kScene), Mode::kRealtime);
  h.start();
  ASSERT_TRUE(h.wait([&] { return h.out.last.tick >= 50; }));

  h.control(ControlKind::kStep, 1, 5);  // running: a step needs a pause first
  EXPECT_EQ(h.reply_to(1).outcome, Outcome::kNotAllowed);
  EXPECT_EQ(h.reply_to(1).note, ReplyNote::kStepNeedsPause);

  h.control(ControlKind::kPause, 2);
  const Reply paused = h.reply_to(2);
  ASSERT_EQ(paused.outcome, Outcome::kOk);
  std::this_thread::sleep_for(100ms);
  EXPECT_LE(h.last_state().tick, paused.tick);  // no tick while paused

  h.control(ControlKind::kStep, 3, 3);
  const Reply stepped = h.reply_to(3);
  EXPECT_EQ(stepped.outcome, Outcome::kOk);
  EXPECT_EQ(stepped.tick, paused.tick + 3);
  EXPECT_EQ(h.last_state().tick, paused.tick + 3);

  h.control(ControlKind::kResume, 4);
  ASSERT_EQ(h.reply_to(4).outcome, Outcome::kOk);
  ASSERT_TRUE(h.wait([&] { return h.out.last.tick >= stepped.tick + 30; }));

  h.control(ControlKind::kReset, 5);
  ASSERT_EQ(h.reply_to(5).outcome, Outcome::kOk);
  EXPECT_EQ(h.reply_to(5).tick, 0);
  // Running again from the scene's initial state.
  ASSERT_TRUE(h.wait([&] { return h.out.last.tick >= 20; }));
}

// The seconds the loop took from the state of tick `from` to the last one handed over, and that
// last tick (the recorder's own times: a stall of the test's thread does not count).
std::pair<double, std::int64_t> loop_seconds_since(Harness& h, std::int64_t from) {
  const std::lock_guard lock(h.out.mutex);
  const auto& t = h.out.ticks;
  const auto first = std::find(t.begin(), t.end(), from);
  if (first == t.end()) return {-1.0, -1};
  const std::size_t i = static_cast<std::size_t>(first - t.begin());
  return {static_cast<double>(h.out.tick_ns.back() - h.out.tick_ns[i]) * 1e-9, t.back() - from};
}

TEST(Loop, RealtimePublishesEveryPublishEveryTicksAtTheScenesRate) {
  Harness h(make_scene(kScene), Mode::kRealtime);
  h.start();
  ASSERT_TRUE(h.wait([&] { return h.out.last.tick >= 300; }, 3000ms));
  h.stop();
  // Published ticks: 0, 10, 20, ...
  for (std::size_t i = 0; i < h.out.ticks.size(); ++i)
    EXPECT_EQ(h.out.ticks[i], static_cast<std::int64_t>(10 * i));
  // Ticks of 1 ms on absolute deadlines: never sooner than the schedule, and later only by the
  // slots the host held the loop past, which it skips and counts (overruns; a VM here stalls for
  // 100 ms now and then).
  const auto [seconds, ticks] = loop_seconds_since(h, 0);
  ASSERT_GE(ticks, 300);
  const double overruns = static_cast<double>(h.loop().overruns());
  EXPECT_GE(seconds, 1e-3 * static_cast<double>(ticks) - 0.002);
  EXPECT_LE(seconds, 1e-3 * (static_cast<double>(ticks) + overruns) + 0.05)
      << overruns << " overruns";
  const RunTotals t = h.loop().totals();
  EXPECT_GE(t.lateness.count(), 300);
}

TEST(Loop, SetRtfChangesThePace) {
  Harness h(make_scene(kScene), Mode::kRealtime);
  h.start();
  h.control(ControlKind::kSetRtf, 1, 0, 4.0);
  ASSERT_EQ(h.reply_to(1).outcome, Outcome::kOk);
  const std::int64_t tick0 = h.last_state().tick;
  ASSERT_TRUE(h.wait([&] { return h.out.last.tick >= tick0 + 400; }));
  h.stop();
  // 400 ticks of 1 ms at 4x: 0.1 s, never sooner (the deadlines are absolute); at 1x they would
  // take 0.4 s, at 2x 0.2 s. Slots the host held the loop past are skipped and counted (0.25 ms
  // each at 4x); beyond those the bound still tells 4x from 2x.
  const auto [seconds, ticks] = loop_seconds_since(h, tick0);
  ASSERT_GE(ticks, 400);
  const double overruns = static_cast<double>(h.loop().overruns());
  EXPECT_GE(seconds, 0.25e-3 * static_cast<double>(ticks) - 0.001);
  EXPECT_LT(seconds, 0.25e-3 * (static_cast<double>(ticks) + overruns) + 0.05)
      << overruns << " overruns";
}

TEST(Loop, FastModeOutrunsTheClockAndReportsEachSecond) {
  Harness h(make_scene(kScene), Mode::kFast);
  h.start();
  LoopSummary s;
  const auto deadline = std::chrono::steady_clock::now() + 3s;
  bool got = false;
  while (!got && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(50ms);
    got = h.loop().take_summary(s);
  }
  ASSERT_TRUE(got);
  EXPECT_EQ(s.mode, Mode::kFast);
  EXPECT_GT(s.rtf_last_second, 5.0);
  EXPECT_GT(s.ticks_stepped, 5000);
  EXPECT_EQ(s.overruns, 0);
}

TEST(Loop, StopsPromptlyWhilePausedOrSleeping) {
  // A 1 Hz scene sleeps a whole second between ticks: stopping must not wait for it.
  Harness h(make_scene("world { rate_hz: 1 } body { name: \"a\" mass: 1 }"), Mode::kRealtime);
  h.start();
  std::this_thread::sleep_for(50ms);
  const std::int64_t t0 = monotonic_ns();
  h.stop();
  EXPECT_LT(monotonic_ns() - t0, 250'000'000);
}

// A ball dropped on a plane, bouncing with e = 1/2 until it rests: the loop hands each tick's
// contact events over once, in that tick, exactly as the closed form has them. It falls h - r = 1 m
// to its first impact at t1 = sqrt(2 (h - r) / g) with v = g t1, taking the impulse m (1 + e) v;
// each bounce lasts 2 e v / g, e times the one before, so it rests at t1 + 2 e v / (g (1 - e)) =
// 3 t1 (the bounce series summed).
const char* kDropScene = R"(
world { rate_hz: 1000 publish_every: 10 gravity { z: -9.81 }
        material { restitution: 0.5 friction: 0.5 } }
plane { name: "ground" normal { z: 1 } }
body { name: "ball" mass: 2 shape { sphere { radius: 0.1 } } position { x: 0.25 y: -0.5 z: 1.1 } }
)";

TEST(Loop, ContactEventsOfEachTickGoOutInThatTickAsTheClosedFormHasThem) {
  Harness h(make_scene(kDropScene), Mode::kLockstep);
  h.start();
  h.control(ControlKind::kStep, 1, 1500);
  ASSERT_EQ(h.reply_to(1).outcome, Outcome::kOk);
  h.stop();
  const double g = 9.81, m = 2.0, e = 0.5, dt = 1e-3;
  const double t1 = std::sqrt(2.0 * 1.0 / g);
  const auto& c = h.out.contacts;
  ASSERT_GE(c.size(), 3u);
  // The first impact: in the tick whose step holds t1, at t1 to round-off.
  EXPECT_EQ(c[0].kind, rigid::ContactKind::kImpact);
  EXPECT_EQ(c[0].tick, static_cast<std::int64_t>(std::ceil(t1 / dt)));
  EXPECT_EQ(c[0].sim_time, static_cast<double>(c[0].tick) * dt);
  EXPECT_NEAR(c[0].time, t1, 1e-14);
  EXPECT_EQ(c[0].body, 0);
  EXPECT_EQ(c[0].part, 0);
  EXPECT_EQ(c[0].position, (rigid::Vec3{0.25, -0.5, 0.0}));
  EXPECT_EQ(c[0].normal, (rigid::Vec3{0.0, 0.0, 1.0}));
  EXPECT_EQ(c[0].impulse[0], 0.0);
  EXPECT_EQ(c[0].impulse[1], 0.0);
  EXPECT_NEAR(c[0].impulse[2], m * (1.0 + e) * g * t1, 1e-13);
  // The second impact a whole bounce later, with e times the impulse.
  EXPECT_EQ(c[1].kind, rigid::ContactKind::kImpact);
  EXPECT_NEAR(c[1].time, t1 + 2.0 * e * g * t1 / g, 1e-13);
  EXPECT_NEAR(c[1].impulse[2], e * c[0].impulse[2], 1e-13);
  // It rests, last, at 3 t1; every event lies within its tick's step, ticks in order, each tick
  // handed over once.
  EXPECT_EQ(c.back().kind, rigid::ContactKind::kResting);
  EXPECT_NEAR(c.back().time, 3.0 * t1, 1e-13);
  std::int64_t ticks = 0;
  for (std::size_t i = 0; i < c.size(); ++i) {
    SCOPED_TRACE(i);
    EXPECT_GT(c[i].time, static_cast<double>(c[i].tick - 1) * dt - 1e-15);
    EXPECT_LE(c[i].time, static_cast<double>(c[i].tick) * dt + 1e-15);
    EXPECT_EQ(c[i].dropped, 0);
    if (i > 0) {
      EXPECT_LE(c[i - 1].time, c[i].time);
      EXPECT_GE(c[i].tick, c[i - 1].tick);
    }
    if (i == 0 || c[i].tick != c[i - 1].tick) ++ticks;
  }
  EXPECT_EQ(h.out.contact_ticks, ticks);
}

// A world without static parts has no contact events, and the loop offers none.
TEST(Loop, AWorldWithoutStaticPartsOffersNoContactEvents) {
  Harness h(make_scene(kScene), Mode::kLockstep);
  h.start();
  h.control(ControlKind::kStep, 1, 200);
  ASSERT_EQ(h.reply_to(1).outcome, Outcome::kOk);
  h.stop();
  EXPECT_EQ(h.out.contact_ticks, 0);
}

}  // namespace
}  // namespace rigid::loop
