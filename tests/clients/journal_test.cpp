// The journal in one process, without a network: a Loop in fast mode journals a stream of random
// wrenches and controls (resets among them) through a real Journal into a file, allocating
// nothing on the loop thread while it does; rigid-sim's replay of that file reproduces every
// journaled state bit for bit. Then the failure reports: a changed command is a divergence with
// its tick (exit 3), a gap stops the replay (exit 4), a damaged tail is replayed up to the damage.
//
// Its own program: operator new is replaced (tests/support/allocation_counter.hpp) to count the
// allocations on the loop thread.
#include "loop/journal.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <random>
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
  std::int64_t seq = 1, control_seq = 1;
  const auto push = [&](const Command& c) {
    if (queue.try_push(c)) doorbell.ring();
  };
  const auto end = std::chrono::steady_clock::now() + run_for;
  for (int round = 0; std::chrono::steady_clock::now() < end; ++round) {
    for (int i = 0; i < 6; ++i, ++seq) {
      Command c;
      Wrench& w = c.wrench;
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
      push(c);
    }
    Command control;
    control.kind = Command::Kind::kControl;
    if (round % 40 == 39) {
      control.control = Control{9, control_seq++, ControlKind::kReset, 0, 0};
      push(control);
    } else if (round % 40 == 20) {
      control.control = Control{9, control_seq++, ControlKind::kPause, 0, 0};
      push(control);
      control.control = Control{9, control_seq++, ControlKind::kStep, 25, 0};
      push(control);
      control.control = Control{9, control_seq++, ControlKind::kResume, 0, 0};
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
  EXPECT_EQ(r.wrenches + r.controls, run_.published);
}

TEST_F(JournalReplay, AChangedCommandIsADivergenceAtTheFirstStateItReaches) {
  std::vector<msgs::LogRecord> records = read_all(path_);
  // A wrench from the middle on that acts: neither replaced (same source, body, key) nor undone by
  // a reset before the next state. The first state hash after it is then the first to differ
  // (the loop publishes after every tick in which a wrench took effect).
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
           records[i].command().kind() == msgs::CommandRecord::CONTROL)) {
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

}  // namespace
}  // namespace rigid::loop
