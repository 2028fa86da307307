// The journal in one process, without a network: a Loop in fast mode journals a stream of random
// wrenches, controls (resets among them) and edits (set_state of random parts in random frames,
// running and paused, and reset_body) through a real Journal into a file, allocating
// nothing on the loop thread while it does; rigid-sim's replay of that file reproduces every
// journaled state bit for bit. Then the failure reports: a changed command is a divergence with
// its tick (exit 3), a gap stops the replay (exit 4), a damaged tail is replayed up to the damage.
// And a contact-rich run (bodies landing, bouncing, resting and pushed about on a ground plane and
// a ramp, a reset among them): the replay hands over exactly the contact events the loop
// published, bit for bit, and a tick's events changed, missing or added are divergences.
//
// Its own program: operator new is replaced (tests/support/allocation_counter.hpp) to count the
// allocations on the loop thread.
#include "loop/journal.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <bit>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <random>
#include <set>
#include <thread>

#include "allocation_counter.hpp"
#include "common/log_records.hpp"
#include "common/record_file.hpp"
#include "common/replay.hpp"
#include "loop/log.hpp"
#include "loop/loop.hpp"
#include "scene/scene.hpp"
#include "test_dir.hpp"

namespace rigid::loop {
namespace {

using namespace std::chrono_literals;
using rigid::ControlKind;

// Every body model, gravity, drag, a constant load: what a replay must get exactly right.
const std::string kScene = R"(
world { rate_hz: 1000 publish_every: 7 gravity { z: -9.81 } limits { max_ttl: 10 } }
body { name: "puck" mass: 2 linear_drag: 0.3 }
body { name: "sphere" mass: 1 inertia { x: 2 y: 2 z: 2 } angular_drag: 0.01 }
body { name: "top" mass: 1 inertia { x: 1 y: 1 z: 2 } angular_velocity { x: 0.1 z: 5 } }
body { name: "brick" mass: 1 inertia { x: 1 y: 2 z: 3 } angular_velocity { x: 0.1 y: 3 } }
body { name: "rocket" mass: 5 inertia_tensor { xx: 0.45 yy: 0.42 zz: 0.05 xy: 0.01 } }
force { body: "rocket" force { z: 10 } point { x: 0.02 z: -0.5 } frame: BODY }
)";

// The loop's output as rigidd wires it for the journal (states and replies go nowhere here).
class JournalOutput final : public LoopOutput {
 public:
  explicit JournalOutput(Journal& journal) : journal_(journal) {}
  void offer_state(const rigid::StateFrame&, std::int64_t) override {}
  void reply(const Reply&) override {}
  void journal(const common::JournalEntry& e) override { journal_.push(e); }

 private:
  Journal& journal_;
};

msgs::LogHeader header(const scene::Scene& s) {
  msgs::LogHeader h;
  h.set_kind(msgs::LogHeader::JOURNAL);
  h.set_schema_version(common::kLogSchemaVersion);
  h.set_software_version(common::software_version());
  h.set_writer("journal_test");
  h.set_rate_hz(s.rate_hz);
  h.set_scene_text(kScene);
  h.set_wrench_capacity(64);
  return h;
}

struct Journaled {
  std::int64_t accepted = 0;
  std::int64_t published = 0;  // accepted commands handed to the buses
  long loop_allocations = -1;
};

// Runs the loop for `run_for` with random commands, journaling to `path`.
Journaled journal_a_run(const std::string& path, std::chrono::milliseconds run_for) {
  const scene::Scene s = scene::parse_scene(kScene, "journal_test.pbtxt");
  MemoryLog log;
  Journaled result;
  std::atomic<std::int64_t> published{0};
  Journal journal({path, 1 << 16}, header(s), log,
                  [&](const rigid::AcceptedCommand&) { ++published; });
  JournalOutput out(journal);
  LoopConfig config;
  config.mode = rigid::Mode::kFast;
  config.tick_dt = 1.0 / s.rate_hz;
  config.publish_every = s.publish_every;
  config.wrench_capacity = 64;  // small: some wrenches find it full, as live
  config.hash_states = true;
  BoundedQueue<Command> queue(256);
  Doorbell doorbell;
  RejectCounters rejects;
  Loop loop(s.world, config, queue, doorbell, rejects, out);
  journal.start();
  rigid::test::reset_counted_allocations();
  std::thread loop_thread([&] {
    const rigid::test::CountingThread counting;
    loop.run();
  });

  std::mt19937_64 random(20240611);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::int64_t seq = 1, control_seq = 1, edit_seq = 1;
  const auto push = [&](const Command& c) {
    if (queue.try_push(c)) doorbell.ring();
  };
  const auto end = std::chrono::steady_clock::now() + run_for;
  for (int round = 0; std::chrono::steady_clock::now() < end; ++round) {
    for (int i = 0; i < 6; ++i, ++seq) {
      Command c;
      Wrench w;
      w.source = static_cast<std::int64_t>(random() % 4);
      w.seq = seq;
      w.body = static_cast<std::int32_t>(random() % 5);
      w.key = static_cast<std::int32_t>(random() % 3);
      w.force = {10 * unit(random), 10 * unit(random), 10 * unit(random)};
      w.point = {0.3 * unit(random), 0.3 * unit(random), 0.3 * unit(random)};
      w.force_frame = random() % 2 ? rigid::Frame::kBody : rigid::Frame::kWorld;
      if (random() % 3 == 0) w.torque = {unit(random), unit(random), unit(random)};
      w.torque_frame = random() % 2 ? rigid::Frame::kBody : rigid::Frame::kWorld;
      w.ttl = 0.05 * static_cast<double>(random() % 4);
      c.what = w;
      push(c);
    }
    if (round % 5 == 2) {
      // An edit: a random part of a random body's state, or a body reset.
      Edit e;
      e.source = 11;
      e.seq = edit_seq++;
      e.body = static_cast<std::int32_t>(random() % 5);
      if (random() % 4 == 0) {
        e.kind = rigid::EditKind::kResetBody;
      } else {
        e.kind = rigid::EditKind::kSetState;
        e.set = static_cast<std::int32_t>(1 + random() % 15);
        e.position = {unit(random), unit(random), 1 + unit(random)};
        const double n = std::sqrt(4.0);
        e.orientation = {1 / n, unit(random) > 0 ? 1 / n : -1 / n, 1 / n, 1 / n};
        e.linear_velocity = {unit(random), unit(random), unit(random)};
        e.velocity_frame = random() % 2 ? rigid::Frame::kBody : rigid::Frame::kWorld;
        e.angular_velocity = {3 * unit(random), 3 * unit(random), 3 * unit(random)};
        e.angular_velocity_frame = random() % 2 ? rigid::Frame::kBody : rigid::Frame::kWorld;
      }
      Command c;
      c.what = e;
      push(c);
    }
    Command control;
    if (round % 40 == 39) {
      control.what = Control{9, control_seq++, ControlKind::kReset, 0, 0};
      push(control);
    } else if (round % 40 == 20) {
      control.what = Control{9, control_seq++, ControlKind::kPause, 0, 0};
      push(control);
      // Paused: the edited state is published (and hashed) at once, at the paused tick.
      Edit paused;
      paused.source = 11;
      paused.seq = edit_seq++;
      paused.kind = rigid::EditKind::kSetState;
      paused.body = 3;
      paused.set = rigid::kSetAngularVelocity;
      paused.angular_velocity = {0.5, -1, 2};
      Command c;
      c.what = paused;
      push(c);
      control.what = Control{9, control_seq++, ControlKind::kStep, 25, 0};
      push(control);
      control.what = Control{9, control_seq++, ControlKind::kResume, 0, 0};
      push(control);
    }
    std::this_thread::sleep_for(1ms);
  }
  loop.request_stop();
  loop_thread.join();
  journal.stop();
  result.loop_allocations = rigid::test::counted_allocations();
  result.accepted = loop.commands_accepted();
  result.published = published.load();
  return result;
}

common::ReplayReport replay(const std::string& path) {
  common::ReplayOptions o;
  o.journal = path;
  return common::replay(o);
}

std::vector<msgs::LogRecord> read_all(const std::string& path) {
  common::RecordReader reader(path);
  std::vector<msgs::LogRecord> records;
  msgs::LogRecord r;
  while (reader.next(r))
    records.push_back(r);
  return records;
}

void write_all(const std::string& path, const std::vector<msgs::LogRecord>& records) {
  common::RecordWriter w(path, true);
  for (const msgs::LogRecord& r : records)
    w.append(r);
  w.close();
}

// One journaled run for the whole suite (in a directory of its own), read by every test.
class JournalReplay : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new std::filesystem::path(std::filesystem::temp_directory_path() /
                                     ("rigid_journal_test_" + std::to_string(::getpid())));
    std::filesystem::remove_all(*dir_);
    std::filesystem::create_directories(*dir_);
    path_ = file("run.rlog");
    run_ = journal_a_run(path_, 400ms);
  }
  static void TearDownTestSuite() {
    std::filesystem::remove_all(*dir_);
    delete dir_;
  }
  static std::string file(const std::string& name) { return (*dir_ / name).string(); }

  static std::filesystem::path* dir_;
  static std::string path_;
  static Journaled run_;
};
std::filesystem::path* JournalReplay::dir_ = nullptr;
std::string JournalReplay::path_;
Journaled JournalReplay::run_;

TEST_F(JournalReplay, JournalingAllocatesNothingOnTheLoopThread) {
  EXPECT_EQ(run_.loop_allocations, 0);
  EXPECT_GT(run_.accepted, 500);
  EXPECT_GT(run_.published, 500);  // the accepted commands also went to the buses' sink
}

TEST_F(JournalReplay, TheReplayReproducesEveryJournaledStateBitForBit) {
  const common::ReplayReport r = replay(path_);
  EXPECT_EQ(r.exit_status(), 0) << (r.divergence ? r.divergence->what : "");
  EXPECT_FALSE(r.divergence);
  EXPECT_FALSE(r.gap);
  EXPECT_TRUE(r.closed_cleanly);
  EXPECT_TRUE(r.damage.empty());
  EXPECT_GT(r.hashes_compared, 1000);
  EXPECT_GT(r.wrenches, 500);
  EXPECT_GE(r.resets, 2);
  EXPECT_GT(r.edits, 20);  // one every fifth round (the rounds a loaded host runs vary)
  EXPECT_EQ(r.wrenches + r.controls + r.edits, run_.published);
}

TEST_F(JournalReplay, AChangedCommandIsADivergenceAtTheFirstStateItReaches) {
  std::vector<msgs::LogRecord> records = read_all(path_);
  // A wrench from the middle on that acts: neither replaced (same source, body, key) nor undone by
  // a reset or an edit before the next state. The first state hash after it is then the first to
  // differ (the loop publishes after every tick in which a wrench took effect).
  const auto same_key = [](const msgs::CommandRecord& a, const msgs::CommandRecord& b) {
    return b.kind() == msgs::CommandRecord::WRENCH && a.source() == b.source() &&
           a.body_id() == b.body_id() && a.key() == b.key();
  };
  std::size_t changed = records.size() / 2;
  std::int64_t expected = -1;
  for (; changed < records.size() && expected < 0; ++changed) {
    const msgs::LogRecord& r = records[changed];
    if (!r.has_command() || r.command().kind() != msgs::CommandRecord::WRENCH ||
        r.command().force().x() == 0.0) {
      continue;
    }
    for (std::size_t i = changed + 1; i < records.size(); ++i) {
      if (records[i].has_state_hash()) {
        expected = records[i].state_hash().tick();
        break;
      }
      if (records[i].has_command() &&
          (same_key(r.command(), records[i].command()) ||
           records[i].command().kind() == msgs::CommandRecord::CONTROL ||
           records[i].command().kind() == msgs::CommandRecord::EDIT)) {
        break;
      }
    }
    if (expected >= 0) break;
  }
  ASSERT_GE(expected, 0) << "no wrench to change";
  msgs::CommandRecord& c = *records[changed].mutable_command();
  c.mutable_force()->set_x(c.force().x() * (1 + 1e-9));
  const std::int64_t tick = c.tick();
  const std::string path = file("changed.rlog");
  write_all(path, records);
  const common::ReplayReport r = replay(path);
  EXPECT_EQ(r.exit_status(), 3);
  ASSERT_TRUE(r.divergence);
  EXPECT_EQ(r.divergence->tick, expected) << "the wrench took effect at tick " << tick;
  EXPECT_GT(expected, tick);
  EXPECT_NE(r.divergence->journaled, r.divergence->replayed);
}

TEST_F(JournalReplay, AGapStopsTheReplayThere) {
  std::vector<msgs::LogRecord> records = read_all(path_);
  const std::size_t at = records.size() / 3;
  msgs::LogRecord gap;
  gap.mutable_gap()->set_dropped(5);
  gap.mutable_gap()->set_tick(12345);
  records.insert(records.begin() + static_cast<std::ptrdiff_t>(at), gap);
  const std::string path = file("gap.rlog");
  write_all(path, records);
  const common::ReplayReport r = replay(path);
  EXPECT_EQ(r.exit_status(), 4);
  ASSERT_TRUE(r.gap);
  EXPECT_EQ(r.gap->dropped, 5);
  EXPECT_FALSE(r.divergence);
}

TEST_F(JournalReplay, ADamagedTailIsReplayedUpToTheDamage) {
  const std::string full = sim::testing::read_file(path_);
  // Cut inside a record (3 bytes into the first frame that starts past 2/3 of the file): a cut on
  // a frame boundary would leave a shorter, undamaged journal.
  std::uint64_t cut = 0;
  {
    common::RecordReader reader(path_);
    msgs::LogRecord rec;
    while (reader.offset() < full.size() * 2 / 3 && reader.next(rec)) {
    }
    cut = reader.offset() + 3;
  }
  ASSERT_LT(cut, full.size());
  const std::string path = file("cut.rlog");
  sim::testing::write_file(path, full.substr(0, cut));
  const common::ReplayReport r = replay(path);
  EXPECT_EQ(r.exit_status(), 0);
  EXPECT_FALSE(r.damage.empty());
  EXPECT_FALSE(r.closed_cleanly);
  EXPECT_GT(r.hashes_compared, 500);
}

TEST_F(JournalReplay, TheJournalHoldsItsSceneAndAnotherSceneIsRefused) {
  const std::string other = file("other.pbtxt");
  sim::testing::write_file(other, "body { name: \"x\" mass: 1 }\n");
  common::ReplayOptions o;
  o.journal = path_;
  o.scene = other;
  EXPECT_THROW(common::replay(o), common::SceneMismatch);
  const std::string same = file("same.pbtxt");
  sim::testing::write_file(same, kScene);
  o.scene = same;
  EXPECT_EQ(common::replay(o).exit_status(), 0);
}

// ---- Contact events ----

const std::string kContactScene = R"(
world { rate_hz: 500 substeps: 2 publish_every: 5 limits { max_ttl: 10 }
        material { restitution: 0.5 friction: 0.6 } }
plane { name: "ground" normal { z: 1 } }
static { name: "ramp" shape { box { x: 2 y: 1 z: 0.1 } } position { x: 2 z: 0.4 }
         orientation { w: 0.9659258262890683 y: 0.25881904510252074 } material { friction: 0.2 } }
body { name: "ball" density: 500 shape { sphere { radius: 0.1 } } position { z: 0.5 }
       velocity { x: 0.5 } material { restitution: 0.8 } }
body { name: "brick" mass: 1 shape { box { x: 0.2 y: 0.1 z: 0.05 } } position { x: 1.6 z: 0.9 } }
body { name: "pill" mass: 1 shape { capsule { radius: 0.05 length: 0.2 } } position { x: -1 z: 0.3 }
       angular_velocity { y: 8 } }
body { name: "can" mass: 1 shape { cylinder { radius: 0.1 length: 0.3 } } position { y: 1 z: 0.4 }
       velocity { y: -1 } angular_velocity { z: 10 } }
body { name: "dot" mass: 1 position { x: -2 z: 0.2 } velocity { x: 1 } }
)";

// Keeps every tick's contact events the loop hands over, as the buses would send them.
class ContactJournalOutput final : public LoopOutput {
 public:
  explicit ContactJournalOutput(Journal& journal) : journal_(journal) {}
  void offer_state(const rigid::StateFrame&, std::int64_t) override {}
  void reply(const Reply&) override { replies.fetch_add(1, std::memory_order_release); }
  void journal(const common::JournalEntry& e) override { journal_.push(e); }
  void offer_contacts(const rigid::ContactEvents& e) override { live.push_back(e); }
  std::vector<rigid::ContactEvents> live;  // loop thread until it stops
  std::atomic<int> replies{0};             // a step's comes when its last tick is done

 private:
  Journal& journal_;
};

// The loop in lockstep, journaling: steps of a random length, random pushes on random bodies
// (some last across steps), a reset halfway.
std::vector<rigid::ContactEvents> journal_a_contact_run(const std::string& path) {
  const scene::Scene s = scene::parse_scene(kContactScene, "contacts.pbtxt");
  MemoryLog log;
  msgs::LogHeader h = header(s);
  h.set_scene_text(kContactScene);
  Journal journal({path, 1 << 16}, h, log, [](const rigid::AcceptedCommand&) {});
  ContactJournalOutput out(journal);
  LoopConfig config;
  config.mode = rigid::Mode::kLockstep;
  config.tick_dt = 1.0 / s.rate_hz;
  config.substeps = s.substeps;
  config.publish_every = s.publish_every;
  config.wrench_capacity = 64;
  config.hash_states = true;
  BoundedQueue<Command> queue(256);
  Doorbell doorbell;
  RejectCounters rejects;
  Loop loop(s.world, config, queue, doorbell, rejects, out);
  journal.start();
  std::thread loop_thread([&] { loop.run(); });
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::int64_t seq = 1, control_seq = 1;
  const auto push = [&](const Command& c) {
    while (!queue.try_push(c))
      std::this_thread::sleep_for(1ms);
    doorbell.ring();
  };
  for (int round = 0; round < 60; ++round) {
    Command c;
    Wrench& w = c.what.emplace<Wrench>();
    w.source = 1;
    w.seq = seq++;
    w.body = static_cast<std::int32_t>(random() % 5);
    w.key = 0;
    w.force = {8 * unit(random), 8 * unit(random), 12 * unit(random)};
    w.point = {0.05 * unit(random), 0.05 * unit(random), 0.0};
    w.ttl = 0.002 * static_cast<double>(random() % 40);
    push(c);
    Command control;
    control.what = Control{9, control_seq++, round == 30 ? ControlKind::kReset : ControlKind::kStep,
                           static_cast<std::int64_t>(20 + random() % 60), 0};
    push(control);
    // Steps run one request at a time: wait for this one's reply (the run is then the same every
    // time: each wrench acts from the tick after the previous step's last).
    const auto give_up = std::chrono::steady_clock::now() + 10s;
    while (out.replies.load(std::memory_order_acquire) < round + 1 &&
           std::chrono::steady_clock::now() < give_up)
      std::this_thread::sleep_for(1ms);
  }
  std::this_thread::sleep_for(50ms);
  loop.request_stop();
  loop_thread.join();
  journal.stop();
  return std::move(out.live);
}

// Bit patterns, so that -0.0 and 0.0 (or two NaNs) are told apart.
std::vector<std::uint64_t> bits(const rigid::ContactEvents& e) {
  std::vector<std::uint64_t> out{static_cast<std::uint64_t>(e.tick),
                                 std::bit_cast<std::uint64_t>(e.sim_time)};
  for (std::size_t i = 0; i < e.event_count(); ++i) {
    out.push_back(static_cast<std::uint64_t>(e.kinds[i]));
    out.push_back(static_cast<std::uint64_t>(e.bodies[i]));
    out.push_back(static_cast<std::uint64_t>(e.parts[i]));
    out.push_back(std::bit_cast<std::uint64_t>(e.times[i]));
  }
  for (const std::vector<double>* v : {&e.position, &e.normal, &e.impulse})
    for (const double x : *v)
      out.push_back(std::bit_cast<std::uint64_t>(x));
  return out;
}

class ContactJournalReplay : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new std::filesystem::path(std::filesystem::temp_directory_path() /
                                     ("rigid_contact_journal_test_" + std::to_string(::getpid())));
    std::filesystem::remove_all(*dir_);
    std::filesystem::create_directories(*dir_);
    path_ = file("contacts.rlog");
    live_ = new std::vector<rigid::ContactEvents>(journal_a_contact_run(path_));
  }
  static void TearDownTestSuite() {
    std::filesystem::remove_all(*dir_);
    delete dir_;
    delete live_;
  }
  static std::string file(const std::string& name) { return (*dir_ / name).string(); }
  static common::ReplayReport replay_collecting(const std::string& path,
                                                std::vector<rigid::ContactEvents>* out) {
    common::ReplayOptions o;
    o.journal = path;
    return common::replay(o, {}, [out](const rigid::ContactEvents& e) { out->push_back(e); });
  }
  static std::filesystem::path* dir_;
  static std::string path_;
  static std::vector<rigid::ContactEvents>* live_;
};
std::filesystem::path* ContactJournalReplay::dir_ = nullptr;
std::string ContactJournalReplay::path_;
std::vector<rigid::ContactEvents>* ContactJournalReplay::live_ = nullptr;

TEST_F(ContactJournalReplay, TheReplayHandsOverTheLiveContactEventsBitForBit) {
  std::size_t events = 0;
  bool impact = false, resting = false, sliding_or_rolling = false, separate = false;
  for (const rigid::ContactEvents& e : *live_) {
    events += e.event_count();
    for (const rigid::ContactKind k : e.kinds) {
      impact |= k == rigid::ContactKind::kImpact;
      resting |= k == rigid::ContactKind::kResting;
      sliding_or_rolling |= k == rigid::ContactKind::kSliding || k == rigid::ContactKind::kRolling;
      separate |= k == rigid::ContactKind::kSeparate;
    }
  }
  // The run is contact-rich: every kind of event, in many ticks.
  EXPECT_GT(live_->size(), 30u);
  EXPECT_GT(events, 60u);
  EXPECT_TRUE(impact && resting && sliding_or_rolling && separate);

  std::vector<rigid::ContactEvents> replayed;
  const common::ReplayReport r = replay_collecting(path_, &replayed);
  ASSERT_EQ(r.exit_status(), 0) << (r.divergence ? r.divergence->what : "");
  EXPECT_GE(r.resets, 1);
  EXPECT_EQ(r.contact_hashes_compared, static_cast<std::int64_t>(live_->size()));
  EXPECT_EQ(r.contact_events, static_cast<std::int64_t>(events));
  ASSERT_EQ(replayed.size(), live_->size());
  for (std::size_t i = 0; i < replayed.size(); ++i)
    ASSERT_EQ(bits(replayed[i]), bits((*live_)[i])) << "tick " << (*live_)[i].tick;
}

TEST_F(ContactJournalReplay, ChangedMissingOrAddedContactHashesAreDivergences) {
  const std::vector<msgs::LogRecord> records = read_all(path_);
  std::size_t at = 0;
  for (std::size_t i = records.size() / 2; i < records.size() && at == 0; ++i)
    if (records[i].has_contact_hash()) at = i;
  ASSERT_GT(at, 0u);
  const std::int64_t tick = records[at].contact_hash().tick();
  std::vector<rigid::ContactEvents> ignored;

  std::vector<msgs::LogRecord> changed = records;
  changed[at].mutable_contact_hash()->set_hash(changed[at].contact_hash().hash() ^ 1);
  write_all(file("changed.rlog"), changed);
  common::ReplayReport r = replay_collecting(file("changed.rlog"), &ignored);
  EXPECT_EQ(r.exit_status(), 3);
  ASSERT_TRUE(r.divergence);
  EXPECT_EQ(r.divergence->tick, tick);
  EXPECT_NE(r.divergence->what.find("contact events hash mismatch"), std::string::npos);

  std::vector<msgs::LogRecord> missing = records;
  missing.erase(missing.begin() + static_cast<std::ptrdiff_t>(at));
  write_all(file("missing.rlog"), missing);
  r = replay_collecting(file("missing.rlog"), &ignored);
  EXPECT_EQ(r.exit_status(), 3);
  ASSERT_TRUE(r.divergence);
  EXPECT_EQ(r.divergence->tick, tick);
  EXPECT_NE(r.divergence->what.find("the journal none"), std::string::npos) << r.divergence->what;

  // A tick without events given a contact hash: find a state hash whose tick has none.
  std::set<std::int64_t> with_events;
  for (const msgs::LogRecord& rec : records)
    if (rec.has_contact_hash()) with_events.insert(rec.contact_hash().tick());
  std::size_t quiet = 0;
  for (std::size_t i = 1; i < records.size() && quiet == 0; ++i)
    if (records[i].has_state_hash() && records[i].state_hash().tick() > 0 &&
        !with_events.contains(records[i].state_hash().tick()))
      quiet = i;
  ASSERT_GT(quiet, 0u);
  std::vector<msgs::LogRecord> added = records;
  msgs::LogRecord extra;
  extra.mutable_contact_hash()->set_tick(records[quiet].state_hash().tick());
  extra.mutable_contact_hash()->set_hash(42);
  extra.mutable_contact_hash()->set_events(1);
  added.insert(added.begin() + static_cast<std::ptrdiff_t>(quiet), extra);
  write_all(file("added.rlog"), added);
  r = replay_collecting(file("added.rlog"), &ignored);
  EXPECT_EQ(r.exit_status(), 3);
  ASSERT_TRUE(r.divergence);
  EXPECT_EQ(r.divergence->tick, records[quiet].state_hash().tick());
  EXPECT_NE(r.divergence->what.find("the replay none"), std::string::npos) << r.divergence->what;
}

}  // namespace
}  // namespace rigid::loop
