// "No allocation on the loop thread after start-up", proved: operator new is replaced in this test
// program (tests/support/allocation_counter.hpp, every form) to count the allocations made on the
// thread that runs Loop::run(), while the loop is driven through everything it does: ticks in each
// mode, wrenches (new, replaced, expiring, stale), every control request, resets, edits (set_state,
// reset_body, stale; paused and running), refusals, contact events, and the hand-off to real
// Publishers (over a fake bus).
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <memory>
#include <new>
#include <string>
#include <thread>

#include "allocation_counter.hpp"
#include "loop/journal.hpp"
#include "loop/publisher.hpp"
#include "loop_harness.hpp"
#include "rigid.pb.h"

namespace rigid::loop {
namespace {

using namespace std::chrono_literals;
using rigid::ControlKind;
using rigid::Mode;
using testing::Harness;
using testing::make_scene;

// What the server's output does: every state to every publisher, replies to the bus's publisher,
// journal entries to the journal (when there is one, as with rigidd --journal).
class PublishingRecorder : public testing::Recorder {
 public:
  PublishingRecorder(SharedStates& states, Publisher& a, Publisher& b)
      : states_(states), a_(a), b_(b) {}
  void journal(const common::JournalEntry& e) override {
    if (journal_ != nullptr) journal_->push(e);
  }
  void attach(Journal* j) { journal_ = j; }
  // As the server: one slot of the shared states, offered to both buses.
  void offer_state(const rigid::StateFrame& f, std::int64_t arrival_ns) override {
    const int slot = states_.put_copied(f, 2);
    a_.offer_slot(slot, arrival_ns);
    b_.offer_slot(slot, arrival_ns);
    Recorder::offer_state(f, arrival_ns);
  }
  // As the server: the loop writes each state into a free slot in place (output_lends_frames).
  rigid::StateFrame* lend_frame() override { return &states_.lend(); }
  void hand_over_lent(std::int64_t arrival_ns) override {
    const int slot = states_.put_lent(2);
    Recorder::offer_state(states_.frame(slot), arrival_ns);
    a_.offer_slot(slot, arrival_ns);
    b_.offer_slot(slot, arrival_ns);
  }
  void reply(const Reply& r) override {
    a_.reply(r);
    Recorder::reply(r);
  }
  // As the server: a tick's contact events queued for both buses.
  void offer_contacts(const rigid::ContactEvents& e) override {
    (void)a_.offer_contacts(e, 1);
    (void)b_.offer_contacts(e, 1);
    Recorder::offer_contacts(e);
  }
  bool wait_contacts_room(std::size_t events, std::int64_t deadline_ns) override {
    return a_.wait_contacts_room(events, deadline_ns) && b_.wait_contacts_room(events, deadline_ns);
  }

 private:
  SharedStates& states_;
  Publisher& a_;
  Publisher& b_;
  Journal* journal_ = nullptr;
};

const char* kScene = R"(
world { rate_hz: 1000 publish_every: 10 gravity { z: -9.81 } limits { max_ttl: 10 } }
body { name: "puck" mass: 2 }
body { name: "sphere" mass: 1 inertia { x: 2 y: 2 z: 2 } }
body { name: "top" mass: 1 inertia { x: 1 y: 1 z: 2 } angular_velocity { x: 0.1 z: 5 } }
body { name: "brick" mass: 1 inertia { x: 1 y: 2 z: 3 } angular_velocity { x: 0.1 y: 3 } }
body { name: "rocket" mass: 5 inertia { x: 0.45 y: 0.42 z: 0.05 } angular_drag: 0.02 }
force { body: "rocket" force { z: 10 } point { x: 0.02 z: -0.5 } frame: BODY }
)";

// kScene with RK4 and a sixth body whose drag is stiff for RK4 (c dt / m = 5): it moves, diverges
// and is frozen by the physics guard, again after each reset (the loop's fault reporting runs).
const char* kDivergingScene = R"(
world { rate_hz: 1000 publish_every: 10 gravity { z: -9.81 } limits { max_ttl: 10 }
        integrator: "rk4" }
body { name: "puck" mass: 2 }
body { name: "sphere" mass: 1 inertia { x: 2 y: 2 z: 2 } }
body { name: "top" mass: 1 inertia { x: 1 y: 1 z: 2 } angular_velocity { x: 0.1 z: 5 } }
body { name: "brick" mass: 1 inertia { x: 1 y: 2 z: 3 } angular_velocity { x: 0.1 y: 3 } }
body { name: "rocket" mass: 5 inertia { x: 0.45 y: 0.42 z: 0.05 } angular_drag: 0.02 }
body { name: "sled" mass: 1 linear_drag: 5000 use_gravity: false velocity { x: 1 } }
force { body: "rocket" force { z: 10 } point { x: 0.02 z: -0.5 } frame: BODY }
)";

// Bodies dropped, thrown and spun onto a ground plane and a tilted static box (with the stream's
// wrenches pushing them about): contact events in many ticks, rests, slides and separations.
const char* kContactScene = R"(
world { rate_hz: 1000 substeps: 2 publish_every: 10 limits { max_ttl: 10 }
        material { restitution: 0.4 friction: 0.6 } }
plane { name: "ground" normal { z: 1 } }
static { name: "ramp" shape { box { x: 1 y: 1 z: 0.1 } } position { x: 2 z: 0.3 }
         orientation { w: 0.9659258262890683 y: 0.25881904510252074 } }
body { name: "puck" mass: 2 position { z: 0.001 } velocity { x: 0.5 z: -0.5 } }
body { name: "ball" density: 500 shape { sphere { radius: 0.1 } } position { z: 0.102 }
       velocity { x: 1 z: -1 } material { restitution: 0.9 } }
body { name: "brick" mass: 1 shape { box { x: 0.2 y: 0.1 z: 0.05 } } position { x: -1 z: 0.026 }
       velocity { x: 2 } angular_velocity { x: 2 } }
body { name: "pill" mass: 1 shape { capsule { radius: 0.05 length: 0.2 } } position { x: -2 z: 0.06 }
       velocity { z: -2 } angular_velocity { y: 8 } material { restitution: 0.9 } }
body { name: "can" mass: 1 shape { cylinder { radius: 0.1 length: 0.3 } } position { x: 2 z: 0.62 }
       velocity { y: -1 z: -3 } angular_velocity { z: 10 } }
)";

Wrench make_wrench(std::int64_t source, std::int64_t seq, std::int32_t body, std::int32_t key,
                   double ttl) {
  Wrench w;
  w.source = source;
  w.seq = seq;
  w.body = body;
  w.key = key;
  w.force = {1, 2, 3};
  w.point = {0.1, 0.2, 0.3};
  w.force_frame = (seq % 2) ? rigid::Frame::kBody : rigid::Frame::kWorld;
  w.torque = {0.01 * static_cast<double>(seq % 3), 0, 0};
  w.ttl = ttl;
  return w;
}

// A loop wired as the server wires it (states written into slots both publishers read, replies to
// one), fed through its queue like the intake feeds it.
struct Rig {
  Rig(const scene::Scene& s, Mode m, bool hash_states)
      : shape(shaped(s)),
        states(shape),
        a(bus_a, states, log, 256, has_parts(s)),
        b(bus_b, states, log, 256, has_parts(s)),
        out(states, a, b),
        loop(s.world, config(s, m, hash_states), queue, doorbell, rejects, out) {
    out.last = shape;
  }
  static LoopConfig config(const scene::Scene& s, Mode m, bool hash_states) {
    LoopConfig c = Harness::config(s, m);
    c.hash_states = hash_states;
    c.output_lends_frames = true;  // as the server runs it
    return c;
  }
  static bool has_parts(const scene::Scene& s) {
    return !s.world.planes.empty() || !s.world.statics.empty();
  }
  static rigid::StateFrame shaped(const scene::Scene& s) {
    rigid::StateFrame f;
    f.resize(s.world.bodies.size());
    return f;
  }
  void push(const Command& c) {
    if (queue.try_push(c)) doorbell.ring();
  }
  void control(ControlKind k, std::int64_t seq, std::int64_t steps = 0, double rtf = 0) {
    Command c;
    c.what = Control{100, seq, k, steps, rtf};
    push(c);
  }

  transport::NullTransport bus_a, bus_b;
  MemoryLog log;
  rigid::StateFrame shape;
  SharedStates states;
  Publisher a, b;
  PublishingRecorder out;
  BoundedQueue<Command> queue{256};
  Doorbell doorbell;
  RejectCounters rejects;
  Loop loop;
};

// Drives the loop through a varied stream for a while: wrenches on every body with a few keys and
// sources (inserted, replaced, expiring), repeated sequence numbers (refused on the loop thread),
// every control request (some refused: a step while one runs, stale ones), then an idle second
// (paused or lockstep: it republishes and rolls its statistics window).
// With `journaling`, as rigidd --journal runs it: every state hashed on the loop thread and every
// entry pushed to a real Journal writing a file from its own thread.
void expect_no_allocations(Mode mode, bool journaling = false, const char* scene = kScene) {
  Rig rig(make_scene(scene), mode, journaling);
  std::unique_ptr<Journal> journal;
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("loop_allocation_" + std::to_string(getpid()) + ".journal"))
                               .string();
  if (journaling) {
    std::filesystem::remove(path);
    msgs::LogHeader header;
    header.set_kind(msgs::LogHeader::JOURNAL);
    journal = std::make_unique<Journal>(Journal::Options{path}, header, rig.log,
                                        [](const rigid::AcceptedCommand&) {});
    rig.out.attach(journal.get());
    journal->start();
  }
  rig.a.start();
  rig.b.start();
  rigid::test::reset_counted_allocations();
  std::thread loop_thread([&] {
    const rigid::test::CountingThread counting;
    rig.loop.run();
  });

  std::int64_t seq = 1, control_seq = 1, edit_seq = 2;
  const auto end = std::chrono::steady_clock::now() + 600ms;
  for (int round = 0; std::chrono::steady_clock::now() < end; ++round) {
    for (int i = 0; i < 8; ++i, ++seq) {
      Command c;
      c.what =
          make_wrench(seq % 3, seq, static_cast<std::int32_t>(seq % 5),
                      static_cast<std::int32_t>(seq % 4), static_cast<double>(seq % 5) * 0.003);
      rig.push(c);
    }
    Command stale;
    stale.what = make_wrench(0, 1, 0, 0, 0.0);
    rig.push(stale);
    // An edit each round: a set_state (every part, body-frame velocities), a body reset (names
    // of at most 15 characters: DrivenWorld::edit says when a reset allocates), a stale one.
    Command edit;
    Edit e;
    e.source = 5;
    e.seq = round % 7 == 6 ? 1 : edit_seq++;
    e.body = static_cast<std::int32_t>(round % 5);
    e.kind = round % 3 == 0 ? rigid::EditKind::kResetBody : rigid::EditKind::kSetState;
    if (e.kind == rigid::EditKind::kSetState) {
      e.set = rigid::kSetAll;
      e.position = {0.1 * round, 0, 1};
      e.orientation = {0.5, 0.5, 0.5, -0.5};
      e.linear_velocity = {0, 1, 0};
      e.velocity_frame = rigid::Frame::kBody;
      e.angular_velocity = {0, 0, 2};
      e.angular_velocity_frame = rigid::Frame::kBody;
    }
    edit.what = e;
    rig.push(edit);
    switch (round % 6) {
      case 0:
        rig.control(ControlKind::kPause, control_seq++);
        break;
      case 1:
        rig.control(ControlKind::kStep, control_seq++, 7);
        break;
      case 2:
        rig.control(ControlKind::kStep, control_seq++, 3);
        rig.control(ControlKind::kResume, control_seq++);
        break;
      case 3:
        rig.control(ControlKind::kSetRtf, control_seq++, 0, round % 2 ? 2.0 : 1.0);
        break;
      case 4:
        if (round % 4 == 0) rig.control(ControlKind::kReset, control_seq++);
        break;
      default:
        rig.control(ControlKind::kPause, control_seq - 5);  // stale
        break;
    }
    std::this_thread::sleep_for(2ms);
  }
  rig.control(ControlKind::kPause, control_seq++);
  std::this_thread::sleep_for(1200ms);
  rig.loop.request_stop();
  loop_thread.join();
  rig.a.stop();
  rig.b.stop();
  if (journal) {
    journal->stop();
    EXPECT_GT(journal->records(), 100);  // commands and state hashes reached the file
    EXPECT_EQ(journal->dropped(), 0);
    std::filesystem::remove(path);
  }

  EXPECT_EQ(rigid::test::counted_allocations(), 0) << "allocations on the loop thread";
  // The run did what it was meant to: ticks, accepted and refused commands, replies, states.
  EXPECT_GT(rig.loop.totals().ticks_stepped, 100);
  EXPECT_GT(rig.loop.commands_accepted(), 100);
  EXPECT_GT(rig.rejects.counts().stale_sequence, 10);
  EXPECT_GT(rig.out.replies.size(), 20u);
  EXPECT_GT(rig.a.states_sent(), 10);
  EXPECT_GT(rig.b.states_sent(), 10);
  if (scene == kContactScene) {
    EXPECT_GT(rig.out.contact_ticks, 10) << "ticks with contact events";
    EXPECT_GT(rig.a.contacts_sent(), 10);
    EXPECT_GT(rig.b.contacts_sent(), 10);
  }
  if (scene == kDivergingScene) {
    FrozenBody f;
    ASSERT_TRUE(rig.loop.take_frozen(f)) << "the sled was never frozen";
    EXPECT_EQ(f.body, 5);
    EXPECT_FALSE(rig.loop.take_frozen(f));  // reported once, however often it froze
  }
}

TEST(LoopAllocation, RealtimeModeAllocatesNothingOnTheLoopThread) {
  expect_no_allocations(Mode::kRealtime);
}

TEST(LoopAllocation, FastModeAllocatesNothingOnTheLoopThread) {
  expect_no_allocations(Mode::kFast);
}

TEST(LoopAllocation, LockstepModeAllocatesNothingOnTheLoopThread) {
  expect_no_allocations(Mode::kLockstep);
}

TEST(LoopAllocation, JournalingAllocatesNothingOnTheLoopThread) {
  expect_no_allocations(Mode::kFast, true);
}

TEST(LoopAllocation, AFrozenBodyAllocatesNothingOnTheLoopThread) {
  expect_no_allocations(Mode::kFast, false, kDivergingScene);
}

TEST(LoopAllocation, ContactEventsAllocateNothingOnTheLoopThread) {
  expect_no_allocations(Mode::kFast, false, kContactScene);
}

TEST(LoopAllocation, ContactEventsInLockstepAllocateNothingOnTheLoopThread) {
  expect_no_allocations(Mode::kLockstep, false, kContactScene);
}

TEST(LoopAllocation, JournalingContactEventsAllocatesNothingOnTheLoopThread) {
  expect_no_allocations(Mode::kFast, true, kContactScene);
}

TEST(LoopAllocation, TheCounterSeesAllocations) {
  // The instrument works: allocations on a counting thread are counted, over-aligned ones too
  // (explicit calls: the compiler may elide a new-expression paired with its delete).
  rigid::test::reset_counted_allocations();
  std::thread t([] {
    const rigid::test::CountingThread counting;
    ::operator delete(::operator new(sizeof(int)));
    constexpr std::align_val_t kLine{64};
    ::operator delete(::operator new(64, kLine), kLine);
  });
  t.join();
  EXPECT_EQ(rigid::test::counted_allocations(), 2);
}

}  // namespace
}  // namespace rigid::loop
