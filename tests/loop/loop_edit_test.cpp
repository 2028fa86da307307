// Edits of the running world through the loop (an in-memory output): a set_state made between two
// ticks, answered with its tick, published at once while paused and stepped from by the next tick
// (checked bit for bit against a World given the same state); parts in the body frame turned by
// the orientation after the edit; the parts not set kept; reset_body back to the scene state with
// its wrenches dropped, the others untouched; stale sequence numbers refused; each edit journaled
// as made.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <thread>
#include <variant>

#include "loop/loop.hpp"
#include "loop_harness.hpp"
#include "physics/world.hpp"

namespace rigid::loop {
namespace {
namespace edit_test {  // (this directory's tests are built as one unit: names of its own)

using namespace std::chrono_literals;
using rigid::ControlKind;
using rigid::Mode;
using rigid::Outcome;
using testing::Harness;
using testing::make_scene;

// No gravity: a point mass, a general body turned 90 degrees about z, a spinning top.
const char* kScene = R"(
world { rate_hz: 1000 publish_every: 10 gravity { z: 0 } limits { max_ttl: 10 } }
body { name: "puck" mass: 2 }
body { name: "brick" mass: 1 inertia { x: 1 y: 2 z: 3 } orientation { w: 0.7071067811865476 z: 0.7071067811865476 } }
body { name: "top" mass: 1 inertia { x: 1 y: 1 z: 2 } angular_velocity { x: 0.1 z: 5 } }
)";

constexpr std::int32_t kPuck = 0, kBrick = 1, kTop = 2;

Edit set_state(std::int64_t seq, std::int32_t body, std::int32_t set) {
  Edit e;
  e.source = 7;
  e.seq = seq;
  e.kind = rigid::EditKind::kSetState;
  e.body = body;
  e.set = set;
  return e;
}

Edit reset_body(std::int64_t seq, std::int32_t body) {
  Edit e;
  e.source = 7;
  e.seq = seq;
  e.kind = rigid::EditKind::kResetBody;
  e.body = body;
  return e;
}

std::vector<std::uint64_t> bits(const std::vector<double>& v) {
  std::vector<std::uint64_t> out;
  for (const double x : v)
    out.push_back(std::bit_cast<std::uint64_t>(x));
  return out;
}

// A state frame's body i as a physics state.
physics::BodyState body_state(const rigid::StateFrame& f, std::size_t i) {
  physics::BodyState s;
  s.p_WBo = {f.position[3 * i], f.position[3 * i + 1], f.position[3 * i + 2]};
  s.q_WB = physics::Quat(f.orientation[4 * i], f.orientation[4 * i + 1], f.orientation[4 * i + 2],
                         f.orientation[4 * i + 3]);
  s.v_WBo = {f.linear_velocity[3 * i], f.linear_velocity[3 * i + 1], f.linear_velocity[3 * i + 2]};
  s.w_WB = {f.angular_velocity[3 * i], f.angular_velocity[3 * i + 1],
            f.angular_velocity[3 * i + 2]};
  return s;
}

// Waits for a published state satisfying pred and returns it.
template <class Pred>
rigid::StateFrame state_where(Harness& h, Pred pred,
                              std::chrono::milliseconds patience = std::chrono::seconds(5)) {
  rigid::StateFrame found;
  EXPECT_TRUE(h.wait(
      [&] {
        if (!pred(h.out.last)) return false;
        found = h.out.last;
        return true;
      },
      patience));
  return found;
}

TEST(LoopEdit, PausedSetStateIsPublishedAtOnceAndTheNextTickStepsFromIt) {
  const scene::Scene scene = make_scene(kScene);
  Harness h(scene, Mode::kLockstep);
  h.start();
  h.control(ControlKind::kStep, 1, 5);
  ASSERT_EQ(h.reply_to(1).tick, 5);
  const std::int64_t before = [&] {
    const std::lock_guard lock(h.out.mutex);
    return h.out.states;
  }();

  Edit e = set_state(101, kPuck, rigid::kSetPosition | rigid::kSetLinearVelocity);
  e.position = {1, 2, 3};
  e.linear_velocity = {0.5, -0.25, 0};
  h.edit(e);
  const Reply r = h.reply_to(101);
  EXPECT_EQ(r.outcome, Outcome::kOk);
  EXPECT_EQ(r.kind, rigid::kReplyToEdit);
  EXPECT_EQ(r.edit, rigid::EditKind::kSetState);
  EXPECT_EQ(r.tick, 5);  // made between ticks 5 and 6
  // Paused: the edited state at once, as tick 5 again (not a second later, when a paused loop
  // republishes its state for late subscribers).
  const rigid::StateFrame edited = state_where(
      h, [&](const rigid::StateFrame& f) { return f.position[0] == 1.0; }, 500ms);
  EXPECT_EQ(edited.tick, 5);
  EXPECT_EQ(std::vector<double>(edited.position.begin(), edited.position.begin() + 3),
            (std::vector<double>{1, 2, 3}));
  EXPECT_EQ(std::vector<double>(edited.linear_velocity.begin(), edited.linear_velocity.begin() + 3),
            (std::vector<double>{0.5, -0.25, 0}));
  {
    const std::lock_guard lock(h.out.mutex);
    EXPECT_EQ(h.out.states, before + 1);  // one state for the edit, no tick
  }

  // The next tick steps from it: the same as a World stepped 5 ticks, given that state, stepped 1.
  physics::World reference(scene.world);
  reference.step(5 * scene.substeps);
  physics::BodyState s = reference.state(kPuck);
  s.p_WBo = {1, 2, 3};
  s.v_WBo = {0.5, -0.25, 0};
  reference.set_state(kPuck, s);
  reference.step(scene.substeps);
  h.control(ControlKind::kStep, 2, 1);
  ASSERT_EQ(h.reply_to(2).tick, 6);
  const rigid::StateFrame next = h.last_state();
  ASSERT_EQ(next.tick, 6);
  for (std::int32_t id : {kPuck, kBrick, kTop}) {
    SCOPED_TRACE(id);
    const physics::BodyState want = reference.state(id);
    const physics::BodyState got = body_state(next, static_cast<std::size_t>(id));
    EXPECT_EQ(got.p_WBo, want.p_WBo);
    EXPECT_EQ(got.v_WBo, want.v_WBo);
    EXPECT_EQ(got.q_WB.coeffs(), want.q_WB.coeffs());
    EXPECT_EQ(got.w_WB, want.w_WB);
  }

  // Journaled as made: the edit, with its tick and resolved body.
  const std::lock_guard lock(h.out.mutex);
  const auto it = std::find_if(
      h.out.journaled.begin(), h.out.journaled.end(),
      [](const common::JournalEntry& j) { return std::holds_alternative<Edit>(j.what); });
  ASSERT_NE(it, h.out.journaled.end());
  EXPECT_EQ(it->tick, 5);
  const Edit& journaled = std::get<Edit>(it->what);
  EXPECT_EQ(journaled.body, kPuck);
  EXPECT_EQ(journaled.seq, 101);
  EXPECT_EQ(journaled.set, rigid::kSetPosition | rigid::kSetLinearVelocity);
  EXPECT_EQ(journaled.position, e.position);
}

TEST(LoopEdit, RunningASetStateLandsOnTheNextTick) {
  Harness h(make_scene(kScene), Mode::kRealtime);
  h.start();
  ASSERT_TRUE(h.wait([&] { return h.out.states >= 3; }));
  Edit e = set_state(101, kPuck, rigid::kSetPosition | rigid::kSetLinearVelocity);
  e.position = {5, 0, 0};
  e.linear_velocity = {1, 0, 0};
  h.edit(e);
  const Reply r = h.reply_to(101);
  ASSERT_EQ(r.outcome, Outcome::kOk);
  const std::int64_t t = r.tick;
  // The state of tick t + 1 is published (not only every 10th), the first stepped from the edit.
  ASSERT_TRUE(h.wait([&] {
    return std::find(h.out.ticks.begin(), h.out.ticks.end(), t + 1) != h.out.ticks.end();
  }));
  h.control(ControlKind::kPause, 1);
  const std::int64_t paused_at = h.reply_to(1).tick;
  const rigid::StateFrame s =
      state_where(h, [&](const rigid::StateFrame& f) { return f.tick == paused_at; });
  // No force, no gravity: x = 5 + (ticks since the edit) x 1 m/s x 1 ms.
  EXPECT_NEAR(s.position[0], 5.0 + static_cast<double>(paused_at - t) * 1e-3, 1e-12);
  EXPECT_EQ(s.linear_velocity[0], 1.0);
}

TEST(LoopEdit, BodyFrameVelocitiesTurnWithTheOrientationTheBodyHasAfterTheEdit) {
  Harness h(make_scene(kScene), Mode::kLockstep);
  h.start();
  // The brick turned 90 degrees about z (as the scene has it), given body-frame velocities.
  Edit e = set_state(
      101, kBrick, rigid::kSetOrientation | rigid::kSetLinearVelocity | rigid::kSetAngularVelocity);
  e.orientation = {std::sqrt(0.5), 0, 0, std::sqrt(0.5)};
  e.linear_velocity = {1, 0, 0};
  e.velocity_frame = rigid::Frame::kBody;
  e.angular_velocity = {0, 2, 0};
  e.angular_velocity_frame = rigid::Frame::kBody;
  h.edit(e);
  ASSERT_EQ(h.reply_to(101).outcome, Outcome::kOk);
  rigid::StateFrame f = state_where(h, [](const rigid::StateFrame& s) {
    return std::abs(s.linear_velocity[3 * kBrick + 1] - 1.0) < 1e-12;
  });
  // B's x is W's y, B's y is W's -x.
  EXPECT_NEAR(f.linear_velocity[3 * kBrick + 0], 0.0, 1e-15);
  EXPECT_NEAR(f.linear_velocity[3 * kBrick + 1], 1.0, 1e-15);
  EXPECT_NEAR(f.angular_velocity[3 * kBrick + 0], -2.0, 1e-14);
  EXPECT_NEAR(f.angular_velocity[3 * kBrick + 1], 0.0, 1e-14);

  // Without an orientation in the edit, the body's own (still 90 degrees about z) turns it.
  Edit v = set_state(102, kBrick, rigid::kSetLinearVelocity);
  v.linear_velocity = {0, 3, 0};
  v.velocity_frame = rigid::Frame::kBody;
  h.edit(v);
  ASSERT_EQ(h.reply_to(102).outcome, Outcome::kOk);
  f = state_where(h, [](const rigid::StateFrame& s) {
    return std::abs(s.linear_velocity[3 * kBrick] + 3.0) < 1e-12;
  });
  EXPECT_NEAR(f.linear_velocity[3 * kBrick + 1], 0.0, 1e-15);
  // The world frame is the default: as given.
  Edit w = set_state(103, kBrick, rigid::kSetLinearVelocity);
  w.linear_velocity = {0, 0, 4};
  h.edit(w);
  ASSERT_EQ(h.reply_to(103).outcome, Outcome::kOk);
  f = state_where(
      h, [](const rigid::StateFrame& s) { return s.linear_velocity[3 * kBrick + 2] == 4.0; });
  EXPECT_EQ(f.linear_velocity[3 * kBrick + 0], 0.0);
}

TEST(LoopEdit, PartsNotSetKeepTheirValues) {
  Harness h(make_scene(kScene), Mode::kLockstep);
  h.start();
  h.control(ControlKind::kStep, 1, 50);
  ASSERT_EQ(h.reply_to(1).outcome, Outcome::kOk);
  const rigid::StateFrame before = h.last_state();
  Edit e = set_state(101, kTop, rigid::kSetPosition);
  e.position = {0, 0, 7};
  h.edit(e);
  ASSERT_EQ(h.reply_to(101).outcome, Outcome::kOk);
  const rigid::StateFrame after =
      state_where(h, [](const rigid::StateFrame& s) { return s.position[3 * kTop + 2] == 7.0; });
  // The top keeps its spin and orientation (to round-off: the world keeps them in the top's
  // principal frame) and its zero velocity; the others are untouched, bit for bit.
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_NEAR(after.angular_velocity[3 * kTop + k], before.angular_velocity[3 * kTop + k], 1e-14);
    EXPECT_EQ(after.linear_velocity[3 * kTop + k], before.linear_velocity[3 * kTop + k]);
  }
  for (std::size_t k = 0; k < 4; ++k)
    EXPECT_NEAR(after.orientation[4 * kTop + k], before.orientation[4 * kTop + k], 1e-15);
  EXPECT_EQ(bits(std::vector<double>(after.position.begin(), after.position.begin() + 6)),
            bits(std::vector<double>(before.position.begin(), before.position.begin() + 6)));
  EXPECT_EQ(bits(std::vector<double>(after.orientation.begin(), after.orientation.begin() + 8)),
            bits(std::vector<double>(before.orientation.begin(), before.orientation.begin() + 8)));
}

TEST(LoopEdit, ResetBodyRestoresItsSceneStateAndDropsOnlyItsWrenches) {
  const scene::Scene scene = make_scene(kScene);
  Harness h(scene, Mode::kLockstep);
  h.start();
  Wrench on_puck;
  on_puck.source = 1;
  on_puck.seq = 1;
  on_puck.body = kPuck;
  on_puck.force = {4, 0, 0};
  on_puck.ttl = 5;
  h.wrench(on_puck);
  Wrench on_brick = on_puck;
  on_brick.seq = 2;
  on_brick.body = kBrick;
  h.wrench(on_brick);
  h.control(ControlKind::kStep, 1, 20);
  ASSERT_EQ(h.reply_to(1).outcome, Outcome::kOk);
  const rigid::StateFrame pushed = h.last_state();
  ASSERT_GT(pushed.linear_velocity[0], 0.0);

  h.edit(reset_body(101, kPuck));
  const Reply r = h.reply_to(101);
  EXPECT_EQ(r.outcome, Outcome::kOk);
  EXPECT_EQ(r.edit, rigid::EditKind::kResetBody);
  EXPECT_EQ(r.tick, 20);  // the world's tick goes on
  const rigid::StateFrame reset =
      state_where(h, [](const rigid::StateFrame& s) { return s.position[0] == 0.0; });
  EXPECT_EQ(reset.tick, 20);
  const physics::BodySpec spec = scene.world.bodies[kPuck];
  EXPECT_EQ(body_state(reset, kPuck).p_WBo, spec.p_WBo);
  EXPECT_EQ(body_state(reset, kPuck).v_WBo, spec.v_WBo);
  // The other bodies are as they were.
  EXPECT_EQ(bits(std::vector<double>(reset.position.begin() + 3, reset.position.end())),
            bits(std::vector<double>(pushed.position.begin() + 3, pushed.position.end())));
  EXPECT_EQ(
      bits(std::vector<double>(reset.linear_velocity.begin() + 3, reset.linear_velocity.end())),
      bits(std::vector<double>(pushed.linear_velocity.begin() + 3, pushed.linear_velocity.end())));

  // Its wrench is gone (the puck stays at rest); the brick's still pushes.
  h.control(ControlKind::kStep, 2, 10);
  ASSERT_EQ(h.reply_to(2).outcome, Outcome::kOk);
  const rigid::StateFrame later = h.last_state();
  EXPECT_EQ(later.position[0], 0.0);
  EXPECT_EQ(later.linear_velocity[0], 0.0);
  EXPECT_GT(later.linear_velocity[3 * kBrick], pushed.linear_velocity[3 * kBrick]);
}

TEST(LoopEdit, AStaleSequenceNumberIsRefusedAndChangesNothing) {
  Harness h(make_scene(kScene), Mode::kLockstep);
  h.start();
  Edit e = set_state(105, kPuck, rigid::kSetPosition);
  e.position = {1, 0, 0};
  h.edit(e);
  ASSERT_EQ(h.reply_to(105).outcome, Outcome::kOk);
  Edit again = set_state(104, kPuck, rigid::kSetPosition);
  again.position = {9, 0, 0};
  h.edit(again);
  const Reply r = h.reply_to(104);
  EXPECT_EQ(r.outcome, Outcome::kInvalid);
  EXPECT_EQ(r.note, ReplyNote::kStaleSequence);
  EXPECT_EQ(r.detail, 105);
  EXPECT_EQ(r.kind, rigid::kReplyToEdit);
  std::this_thread::sleep_for(20ms);
  EXPECT_EQ(h.last_state().position[0], 1.0);
  EXPECT_EQ(h.rejects().counts().stale_sequence, 1);
}

}  // namespace edit_test
}  // namespace
}  // namespace rigid::loop
