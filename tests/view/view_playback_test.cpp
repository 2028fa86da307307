// rigid-view FILE: the playback commands checked, refused in the wrong mode; a recording (written
// here with rigid-record's writer, or as an lcm-logger log) loaded into the page's frames, with
// its damaged tail, resets, scene changes and memory limit; a journal (written here as rigidd's
// loop and journal write one) replayed into exactly the states rigidd published, and refused when
// its replay diverges; the playback clock's play, pause, seek and speed, driven with made-up times.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "common/driven_world.hpp"
#include "common/journal_entry.hpp"
#include "common/log_records.hpp"
#include "common/record_file.hpp"
#include "common/state_conversion.hpp"
#include "common/state_hash.hpp"
#include "drift.hpp"
#include "playback_clock.hpp"
#include "protocol.hpp"
#include "recording_source.hpp"
#include "scene/scene.hpp"
#include "transport/lcm/lcm_codec.hpp"
#include "transport/topic.hpp"
#include "view_options.hpp"

namespace rigid::view {
namespace {

// A state frame's per-body drifts (protocol.hpp), energy's then momentum's, and the frame with
// them zeroed: the rest of a loaded frame is compared with encode_state's bit for bit, the drifts
// (drift.hpp) on their own.
std::pair<std::vector<float>, std::vector<float>> drifts_of(const std::string& f) {
  std::uint32_t n = 0, flags = 0;
  std::memcpy(&n, f.data() + 4, 4);
  std::memcpy(&flags, f.data() + 12, 4);
  const std::size_t at = kStateHeaderBytes + 13 * ((flags & kStateFloat32) ? 4 : 8) * n;
  std::vector<float> e(n), m(n);
  std::memcpy(e.data(), f.data() + at, 4 * n);
  std::memcpy(m.data(), f.data() + at + 4 * n, 4 * n);
  return {e, m};
}
std::string zero_drifts(std::string f) {
  std::uint32_t n = 0, flags = 0;
  std::memcpy(&n, f.data() + 4, 4);
  std::memcpy(&flags, f.data() + 12, 4);
  const std::size_t at = kStateHeaderBytes + 13 * ((flags & kStateFloat32) ? 4 : 8) * n;
  std::fill(f.begin() + static_cast<std::ptrdiff_t>(at),
            f.begin() + static_cast<std::ptrdiff_t>(at + 8 * n), '\0');
  return f;
}

namespace fs = std::filesystem;
using namespace std::chrono_literals;

std::string refusal(std::string_view text) {
  auto r = parse_command(text);
  return std::holds_alternative<std::string>(r) ? std::get<std::string>(r) : std::string();
}
PageCommand command(std::string_view text) {
  auto r = parse_command(text);
  EXPECT_TRUE(std::holds_alternative<PageCommand>(r)) << text << ": " << refusal(text);
  return std::holds_alternative<PageCommand>(r) ? std::get<PageCommand>(r) : PageCommand{};
}

TEST(ViewPlaybackProtocol, AcceptsPlayPauseSeekAndSpeed) {
  EXPECT_EQ(command(R"({"op":"play","id":1})").op, Op::kPlay);
  EXPECT_EQ(command(R"({"op":"pause","id":2})").op, Op::kPause);
  const PageCommand by_tick = command(R"({"op":"seek","id":3,"tick":1234})");
  EXPECT_EQ(by_tick.op, Op::kSeek);
  EXPECT_EQ(by_tick.tick, 1234);
  EXPECT_FALSE(by_tick.time.has_value());
  const PageCommand by_time = command(R"({"op":"seek","id":4,"time":2.5})");
  EXPECT_EQ(by_time.tick, -1);
  ASSERT_TRUE(by_time.time.has_value());
  EXPECT_EQ(*by_time.time, 2.5);
  EXPECT_EQ(command(R"({"op":"speed","id":5,"speed":0.25})").speed, 0.25);
  EXPECT_EQ(command(R"({"op":"speed","id":5,"speed":64})").speed, kMaxPlaybackSpeed);
}

TEST(ViewPlaybackProtocol, RefusesBadValuesWithAReason) {
  EXPECT_EQ(refusal(R"({"op":"speed","id":1,"speed":65})"),
            "speed: expected a number in [1/64, 64]");
  EXPECT_EQ(refusal(R"({"op":"speed","id":1,"speed":0})"),
            "speed: expected a number in [1/64, 64]");
  EXPECT_EQ(refusal(R"({"op":"speed","id":1,"speed":"fast"})"),
            "speed: expected a number in [1/64, 64]");
  EXPECT_EQ(refusal(R"({"op":"speed","id":1})"), "speed: missing speed");
  EXPECT_EQ(refusal(R"({"op":"seek","id":1})"), "seek: needs one of tick and time");
  EXPECT_EQ(refusal(R"({"op":"seek","id":1,"tick":5,"time":1})"),
            "seek: needs one of tick and time");
  EXPECT_EQ(refusal(R"({"op":"seek","id":1,"tick":-1})"), "tick: expected an integer in [0, 2^53]");
  EXPECT_EQ(refusal(R"({"op":"seek","id":1,"tick":1.5})"),
            "tick: expected an integer in [0, 2^53]");
  EXPECT_EQ(refusal(R"({"op":"seek","id":1,"time":2e12})"),
            "time: expected a number of seconds in [-1e12, 1e12]");
  EXPECT_EQ(refusal(R"({"op":"seek","id":1,"time":[1]})"),
            "time: expected a number of seconds in [-1e12, 1e12]");
  EXPECT_EQ(refusal(R"({"op":"seek","tick":3})"), "seek: missing id");
  EXPECT_EQ(refusal(R"({"op":"play","id":1,"speed":2})"), "play: unexpected field");
  EXPECT_EQ(refusal(R"({"op":"pause","id":1,"tick":2})"), "pause: unexpected field");
  EXPECT_EQ(refusal(R"({"op":"push","body":1,"force":[1,0,0],"point":[0,0,0],"tick":2})"),
            "push: unexpected field");
}

TEST(ViewPlaybackProtocol, EachModeRefusesTheOthersCommands) {
  const auto in = [](std::string_view text, bool playback) {
    return refusal_in_mode(command(text), playback);
  };
  // Playback: rigidd's controls and pushes have no rigidd to go to.
  EXPECT_EQ(in(R"({"op":"pause","id":1})", true), "");
  EXPECT_EQ(in(R"({"op":"play","id":1})", true), "");
  EXPECT_EQ(in(R"({"op":"seek","id":1,"tick":0})", true), "");
  EXPECT_EQ(in(R"({"op":"speed","id":1,"speed":2})", true), "");
  for (const char* live : {R"({"op":"resume","id":1})", R"({"op":"reset","id":1})",
                           R"({"op":"step","id":1,"steps":2})",
                           R"({"op":"push","body":1,"force":[1,0,0],"point":[0,0,0]})"}) {
    const std::string why = in(live, true);
    EXPECT_NE(why.find("not while playing a recording"), std::string::npos) << live << ": " << why;
  }
  // Live: no recording to play.
  EXPECT_EQ(in(R"({"op":"pause","id":1})", false), "");
  EXPECT_EQ(in(R"({"op":"step","id":1,"steps":2})", false), "");
  EXPECT_EQ(in(R"({"op":"seek","id":1,"time":0})", false),
            "seek: only when playing a recording (rigid-view FILE)");
  EXPECT_EQ(in(R"({"op":"play","id":1})", false),
            "play: only when playing a recording (rigid-view FILE)");
}

TEST(ViewPlaybackProtocol, HelloSaysTheMode) {
  EXPECT_NE(hello_json(false, 3, true).find(R"("mode":"playback")"), std::string::npos);
  EXPECT_NE(hello_json(false, 3).find(R"("mode":"live")"), std::string::npos);
  PlaybackStatus s;
  s.file = "run \"1\".rlog";
  s.playing = true;
  s.tick = 42;
  s.index = 7;
  s.states = 9;
  const std::string text = playback_json(s);
  EXPECT_NE(text.find(R"("file":"run \"1\".rlog")"), std::string::npos) << text;
  EXPECT_NE(text.find(R"("playing":true)"), std::string::npos) << text;
  EXPECT_NE(text.find(R"("tick":42)"), std::string::npos) << text;
  EXPECT_NE(text.find(R"("index":7,"states":9})"), std::string::npos) << text;
}

TEST(ViewPlaybackOptions, TakesAFileAndOnlyThePrefixOfTheBusOptions) {
  const auto parse = [](std::vector<std::string_view> args) { return parse_options(args); };
  const ViewOptions o = parse({"--listen", "127.0.0.1:0", "run.rlog"});
  EXPECT_EQ(o.file, "run.rlog");
  EXPECT_FALSE(o.prefix_given);
  const ViewOptions p = parse({"--prefix", "robot", "run.log"});
  EXPECT_TRUE(p.prefix_given);
  EXPECT_EQ(p.bus.prefix, "robot");
  EXPECT_TRUE(parse({"--transport", "lcm"}).file.empty());  // live: as before
  EXPECT_EQ(parse({"--max-memory", "64", "run.rlog"}).max_memory_mib, 64);
  EXPECT_EQ(parse({"run.rlog"}).max_memory_mib, 512);
  for (const std::vector<std::string_view>& bad :
       {std::vector<std::string_view>{"--max-memory", "0", "a.rlog"},
        {"--max-memory", "2e3", "a.rlog"},
        {"--max-memory", "1048577", "a.rlog"},
        {"--max-memory", "64"}}) {
    try {
      parse(bad);
      ADD_FAILURE() << "accepted --max-memory " << bad[1];
    } catch (const clients::UsageError& e) {
      EXPECT_EQ(std::string(e.what()).rfind("--max-memory: ", 0), 0u) << e.what();
    }
  }
  try {
    parse({"a.rlog", "b.rlog"});
    ADD_FAILURE() << "two files accepted";
  } catch (const clients::UsageError& e) {
    EXPECT_STREQ(e.what(), "unexpected argument 'b.rlog' (see --help)");
  }
  try {
    parse({"--transport", "lcm", "a.rlog"});
    ADD_FAILURE() << "a bus option accepted with FILE";
  } catch (const clients::UsageError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("--transport: rigid-view FILE plays a recording", 0), 0u)
        << e.what();
  }
  EXPECT_NE(usage().find("[--max-memory MIB]\n                  [--prefix P] FILE"),
            std::string::npos);
}

// ---- recordings -------------------------------------------------------------------------------

SceneDescription two_bodies(std::string name) {
  SceneDescription d;
  d.scene_name = std::move(name);
  d.dt = 0.01;
  d.ids = {4, 9};
  d.names = {"spinner", "ball"};
  d.masses = {1, 2};
  d.inertia = {1, 2, 3, 0, 0, 0, 0.4, 0.4, 0.4, 0, 0, 0};
  d.shape_kinds = {ShapeKind::kBox, ShapeKind::kSphere};
  d.shape_dims = {0.1, 0.2, 0.3, 0.5, 0, 0};
  return d;
}

// A state whose numbers follow from its tick, so that each state of a file is different.
StateFrame state_at(std::int64_t tick, double dt = 0.01) {
  StateFrame s;
  s.tick = tick;
  s.sim_time = static_cast<double>(tick) * dt;
  s.stamp_ns = 1000 + tick;
  s.ids = {4, 9};
  const double a = 0.1 * static_cast<double>(tick);
  s.position = {a, 1, 2, -a, 0.5, 0};
  s.orientation = {std::cos(a / 2), std::sin(a / 2), 0, 0, 1, 0, 0, 0};
  s.linear_velocity = {1, 0, 0, -1, 0, 0};
  s.angular_velocity = {a, 0, 0, 0, 0, 0};
  return s;
}

StatsReport stats_at_tick(std::int64_t tick) {
  StatsReport s;
  s.tick = tick;
  s.sim_time = static_cast<double>(tick) * 0.01;
  s.overruns = 3;
  s.lateness_p99_us = 12.5;
  return s;
}

class RecordingFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("rigid_view_playback_" +
            std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  // A recording as rigid-record writes it: the header's scene, `ticks` states, a SceneRecord
  // before the state at index `scene_change_at` (if >= 0), a LogEnd.
  std::string write(const std::string& name, const std::vector<std::int64_t>& ticks,
                    int scene_change_at = -1,
                    msgs::LogHeader::Kind kind = msgs::LogHeader::RECORDING) {
    const std::string file = path(name);
    common::RecordWriter w(file, false);
    msgs::LogRecord r;
    r.mutable_header()->set_kind(kind);
    r.mutable_header()->set_schema_version(common::kLogSchemaVersion);
    common::to_record(two_bodies("first"), 0, *r.mutable_header()->mutable_scene());
    w.append(r);
    for (std::size_t i = 0; i < ticks.size(); ++i) {
      if (i == 3) {  // Stats, as rigidd sends them once a second
        r.Clear();
        common::to_record(stats_at_tick(ticks[i]), 7, *r.mutable_stats());
        w.append(r);
      }
      if (static_cast<int>(i) == scene_change_at) {
        r.Clear();
        common::to_record(two_bodies("second"), 5, *r.mutable_scene());
        w.append(r);
      }
      r.Clear();
      common::to_record(state_at(ticks[i]), static_cast<std::int64_t>(i) * 10'000'000,
                        *r.mutable_state());
      w.append(r);
    }
    r.Clear();
    r.mutable_end();
    w.append(r);
    w.close();
    return file;
  }

  // A recording of states at `ticks` with accepted commands among them: each written just before
  // the state at index `before` (the end when past the last), as rigid-record writes the two
  // streams in the order they arrive.
  struct Placed {
    std::size_t before = 0;
    AcceptedCommand command;
  };
  std::string write_with_commands(const std::string& name, const std::vector<std::int64_t>& ticks,
                                  const std::vector<Placed>& commands) {
    const std::string file = path(name);
    common::RecordWriter w(file, false);
    msgs::LogRecord r;
    r.mutable_header()->set_kind(msgs::LogHeader::RECORDING);
    r.mutable_header()->set_schema_version(common::kLogSchemaVersion);
    common::to_record(two_bodies("first"), 0, *r.mutable_header()->mutable_scene());
    w.append(r);
    for (std::size_t i = 0; i <= ticks.size(); ++i) {
      for (const Placed& c : commands) {
        if (c.before != i && !(i == ticks.size() && c.before > i)) continue;
        r.Clear();
        common::to_record(c.command, 0, *r.mutable_command());
        w.append(r);
      }
      if (i == ticks.size()) break;
      r.Clear();
      common::to_record(state_at(ticks[i]), 0, *r.mutable_state());
      w.append(r);
    }
    w.close();
    return file;
  }

  fs::path dir_;
};

// A wrench accepted at `tick` (the scenes here step 0.01 s a tick).
AcceptedCommand wrench_at(std::int64_t tick, std::int64_t seq, double ttl, std::int32_t key = 0) {
  AcceptedCommand a;
  a.kind = AcceptedKind::kWrench;
  a.tick = tick;
  a.source = 5;
  a.seq = seq;
  a.key = key;
  a.body_id = 4;
  a.force = {1, 2, 3};
  a.ttl = ttl;
  return a;
}
AcceptedCommand reset_at(std::int64_t tick) {
  AcceptedCommand a;
  a.kind = AcceptedKind::kControl;
  a.command = ControlKind::kReset;
  a.tick = tick;
  a.source = 6;
  a.seq = 1;
  return a;
}

// Where each recorded wrench is shown: seq -> the (stretch, tick) of the states it acts on.
using Shown = std::map<std::int64_t, std::vector<std::pair<std::uint32_t, std::int64_t>>>;
Shown shown_by_seq(const Recording& r) {
  Shown out;
  for (std::size_t i = 0; i < r.states.size(); ++i) {
    for (const std::size_t k : r.wrenches_at(i))
      out[r.wrenches.all()[k].command.seq].emplace_back(r.states[i].stretch, r.states[i].tick);
  }
  return out;
}
// The states (stretch, from + 1 .. last).
std::vector<std::pair<std::uint32_t, std::int64_t>> ticks(std::uint32_t stretch, std::int64_t from,
                                                          std::int64_t last) {
  std::vector<std::pair<std::uint32_t, std::int64_t>> out;
  for (std::int64_t t = from + 1; t <= last; ++t)
    out.emplace_back(stretch, t);
  return out;
}

std::string what_of_load(const std::string& file, const LoadLimits& limits = {}) {
  try {
    (void)load_recording(file, limits);
  } catch (const RecordingError& e) {
    return e.what();
  }
  return "loaded";
}

TEST_F(RecordingFiles, LoadsEveryStateAsThePagesFrame) {
  const std::vector<std::int64_t> ticks{0, 1, 2, 3, 4, 5, 6, 7, 8, 9};
  const std::string file = write("run.rlog", ticks, 6);
  const Recording r = load_recording(file, {});
  EXPECT_EQ(r.kind, "rigid-record recording");
  EXPECT_TRUE(r.note.empty()) << r.note;
  ASSERT_EQ(r.scenes.size(), 2u);
  EXPECT_EQ(r.scenes[0], two_bodies("first"));
  EXPECT_EQ(r.scenes[1], two_bodies("second"));
  ASSERT_EQ(r.states.size(), ticks.size());
  ASSERT_EQ(r.frames.size(), ticks.size());
  for (std::size_t i = 0; i < ticks.size(); ++i) {
    StateFrame s = state_at(ticks[i]);
    s.stamp_ns = 0;  // the recorded stamp says nothing of the page's latency
    const std::uint32_t scene = i < 6 ? 0 : 1;
    EXPECT_EQ(r.states[i].tick, s.tick);
    EXPECT_EQ(r.states[i].sim_time, s.sim_time);
    EXPECT_EQ(r.states[i].position, s.sim_time);  // no reset: the timeline is the sim time
    EXPECT_EQ(r.states[i].scene, scene);
    ASSERT_TRUE(r.frames[i]);
    EXPECT_EQ(zero_drifts(*r.frames[i]), encode_state(s, Recording::generation(scene), {}, {}))
        << "state " << i;
  }
  EXPECT_GT(r.bytes, 10 * r.frames[0]->size());
  // The Stats recorded before state 3 are the HUD's from state 3 on.
  ASSERT_EQ(r.stats.size(), 1u);
  EXPECT_EQ(r.stats_at(2), nullptr);
  for (const std::size_t i : {3u, 4u, 9u}) {
    ASSERT_NE(r.stats_at(i), nullptr) << i;
    EXPECT_EQ(*r.stats_at(i), stats_json(stats_at_tick(3))) << i;
  }
}

TEST_F(RecordingFiles, ATimelineCarriesOnAcrossAReset) {
  const Recording r = load_recording(write("reset.rlog", {10, 11, 12, 0, 1, 2}), {});
  ASSERT_EQ(r.states.size(), 6u);
  for (std::size_t i = 1; i < r.states.size(); ++i)
    EXPECT_GE(r.states[i].position, r.states[i - 1].position) << i;
  EXPECT_EQ(r.states[3].sim_time, 0.0);
  EXPECT_EQ(r.states[3].position, r.states[2].position);  // carries on from where it was
  EXPECT_DOUBLE_EQ(r.states[5].position - r.states[3].position, r.states[5].sim_time);
}

TEST_F(RecordingFiles, ShowsARecordedWrenchExactlyWithTheStatesItsTicksProduced) {
  std::vector<std::int64_t> all(31);
  for (std::size_t i = 0; i < all.size(); ++i)
    all[i] = static_cast<std::int64_t>(i);
  // A pure torque in B accepted at tick 10 for 0.05 s (5 ticks at 0.01 s: the steps 10 -> 15),
  // written late (after the states 10 and 11); a force for one tick (ttl 0) at tick 20, written
  // early; a control that is no reset, ignored.
  AcceptedCommand torque = wrench_at(10, 1, 0.05);
  torque.force = {0, 0, 0};
  torque.torque = {0, 0, 2};
  torque.torque_frame = Frame::kBody;
  AcceptedCommand pause = reset_at(12);
  pause.command = ControlKind::kPause;
  const std::string file =
      write_with_commands("push.rlog", all, {{12, torque}, {13, pause}, {19, wrench_at(20, 2, 0)}});
  const Recording r = load_recording(file, {});
  ASSERT_EQ(r.states.size(), all.size());
  ASSERT_EQ(r.wrenches.all().size(), 2u);
  const Shown shown = shown_by_seq(r);
  EXPECT_EQ(shown.at(1), ticks(0, 10, 15));
  EXPECT_EQ(shown.at(2), ticks(0, 20, 21));
  // What the page gets with state 11: the torque with its frame, and the tick it stops at.
  ASSERT_EQ(r.wrenches_at(11).size(), 1u);
  const RecordedWrench& w = r.wrenches.all()[r.wrenches_at(11)[0]];
  const std::string text = wrenches_json({w.command}, {w.until});
  EXPECT_NE(text.find(R"("tick":10,"ttl":0.050000000000000003,)"), std::string::npos) << text;
  EXPECT_NE(text.find(R"("torque":[0,0,2],"torque_frame":"body","key":0,"until":15})"),
            std::string::npos)
      << text;
}

// The ticks of a recording reset at tick 30: 0..30, then 0..10 again.
std::vector<std::int64_t> reset_at_30_ticks() {
  std::vector<std::int64_t> all;
  for (std::int64_t t = 0; t <= 30; ++t)
    all.push_back(t);
  for (std::int64_t t = 0; t <= 10; ++t)
    all.push_back(t);
  return all;
}

TEST_F(RecordingFiles, ANewerWrenchWithItsKeyOrAResetCutsAWrenchShort) {
  // Ticks 0..30, a reset at tick 30, ticks 0..10 again. A (key 1) from tick 5 for 1 s is replaced
  // by B (key 1) at tick 12; B, for 0.5 s, is cleared by the reset; C comes after the reset, read
  // before the reset's first state. A and B must not show in the second stretch, whose ticks
  // 6..12 they would match, nor C in the first.
  const std::vector<std::int64_t> all = reset_at_30_ticks();
  const std::string file = write_with_commands("reset.rlog", all,
                                               {{6, wrench_at(5, 1, 1.0, 1)},
                                                {13, wrench_at(12, 2, 0.5, 1)},
                                                {31, reset_at(30)},
                                                {31, wrench_at(0, 3, 0.03, 1)}});
  const Recording r = load_recording(file, {});
  ASSERT_EQ(r.states.size(), all.size());
  EXPECT_EQ(r.states[30].stretch, 0u);
  EXPECT_EQ(r.states[31].stretch, 1u);
  const Shown shown = shown_by_seq(r);
  EXPECT_EQ(shown.at(1), ticks(0, 5, 12));  // up to the state B's first step starts from
  EXPECT_EQ(shown.at(2), ticks(0, 12, 30));
  EXPECT_EQ(shown.at(3), ticks(1, 0, 3));
}

TEST_F(RecordingFiles, AResetWrittenAfterItsFirstStateStillSeparatesTheStretches) {
  // As above, but the reset's command (and a wrench D accepted just before it) written after the
  // state of tick 0 that follows it: D belongs to the first stretch (its tick is near that
  // stretch's last), C to the second.
  const std::vector<std::int64_t> all = reset_at_30_ticks();
  const std::string file = write_with_commands("late_reset.rlog", all,
                                               {{13, wrench_at(12, 2, 0.5, 1)},
                                                {32, wrench_at(29, 4, 0.05, 2)},
                                                {32, reset_at(30)},
                                                {33, wrench_at(0, 3, 0.03, 1)}});
  const Recording r = load_recording(file, {});
  const Shown shown = shown_by_seq(r);
  EXPECT_EQ(shown.at(2), ticks(0, 12, 30));
  EXPECT_EQ(shown.at(4), ticks(0, 29, 30));  // cut by the reset at 30
  EXPECT_EQ(shown.at(3), ticks(1, 0, 3));
}

TEST_F(RecordingFiles, RefusesWrenchesBeyondTheMemoryLimit) {
  std::vector<Placed> many;
  for (std::int64_t i = 0; i < 100; ++i)
    many.push_back({4, wrench_at(1, i + 1, 0.01, static_cast<std::int32_t>(i))});  // after all
  const std::string file = write_with_commands("many.rlog", {0, 1, 2, 3}, many);
  const Recording all = load_recording(file, {});
  EXPECT_EQ(all.wrenches.all().size(), 100u);
  EXPECT_EQ(all.wrenches_at(2).size(), 64u);  // the newest kMaxWrenchesShown
  EXPECT_EQ(all.wrenches.all()[all.wrenches_at(2).back()].command.seq, 100);
  LoadLimits limits;
  limits.max_bytes = all.bytes - 1;
  const std::string why = what_of_load(file, limits);
  EXPECT_EQ(why.rfind(file + ": its states and accepted commands need more than 1 MiB", 0), 0u)
      << why;
}

TEST_F(RecordingFiles, PlaysUpToADamagedTail) {
  const std::string file = write("cut.rlog", {0, 1, 2, 3, 4, 5, 6, 7});
  // Cut the file inside its last state (the LogEnd and a few bytes of the state before it).
  const auto size = fs::file_size(file);
  fs::resize_file(file, size - 12);
  const Recording r = load_recording(file, {});
  EXPECT_EQ(r.states.size(), 7u);
  EXPECT_NE(r.note.find("damaged tail"), std::string::npos) << r.note;
  // Cut inside the header: nothing to play.
  fs::resize_file(file, common::kLogPreambleBytes + common::kFrameHeaderBytes + 3);
  const std::string why = what_of_load(file);
  EXPECT_EQ(why.rfind(file + ": no header record", 0), 0u) << why;
}

TEST_F(RecordingFiles, RefusesWhatItCannotPlayInOneLineNamingTheFile) {
  const auto one_line_naming = [](const std::string& why, const std::string& file) {
    EXPECT_EQ(why.find('\n'), std::string::npos) << why;
    EXPECT_EQ(why.rfind(file, 0), 0u) << why;
  };
  const std::string garbage = path("garbage.rlog");
  std::ofstream(garbage) << "this is not a recording at all";
  one_line_naming(what_of_load(garbage), garbage);
  const std::string missing = path("missing.rlog");
  one_line_naming(what_of_load(missing), missing);
  // A journal without its copy of the scene file cannot be replayed.
  const std::string journal = write("run.journal", {0, 1}, -1, msgs::LogHeader::JOURNAL);
  const std::string why = what_of_load(journal);
  one_line_naming(why, journal);
  EXPECT_NE(why.find("cannot replay it"), std::string::npos) << why;
  const std::string empty = write("empty.rlog", {});
  EXPECT_EQ(what_of_load(empty), empty + ": no states to play");
}

TEST_F(RecordingFiles, RefusesAFileLargerThanTheLimit) {
  const std::string file = write("big.rlog", std::vector<std::int64_t>(50, 3));
  const Recording all = load_recording(file, {});
  LoadLimits limits;
  limits.max_bytes = all.bytes - 1;
  const std::string why = what_of_load(file, limits);
  EXPECT_EQ(why.rfind(file + ": its states need more than 1 MiB in memory", 0), 0u) << why;
  EXPECT_NE(why.find("--max-memory"), std::string::npos) << why;
  limits.max_bytes = all.bytes;
  EXPECT_EQ(what_of_load(file, limits), "loaded");
}

// An lcm-logger log (LCM's event log format, big-endian) of rigidd's channels, with `prefix`.
// `commands`: accepted commands on its RIGID_ACCEPTED channel, each after the state `first`.
void write_lcm_log(const std::string& file, const std::string& prefix, int states,
                   const std::vector<std::pair<int, AcceptedCommand>>& commands = {}) {
  const transport::TopicNames names = transport::lcm_channel_names(prefix);
  transport::lcm::Codec codec;
  std::ofstream out(file, std::ios::binary);
  std::int64_t number = 0;
  const auto be = [&out](std::uint64_t v, int bytes) {
    for (int k = bytes - 1; k >= 0; --k)
      out.put(static_cast<char>((v >> (8 * k)) & 0xff));
  };
  const auto event = [&](const std::string& channel, std::span<const std::uint8_t> data) {
    be(0xEDA1DA01u, 4);
    be(static_cast<std::uint64_t>(number++), 8);
    be(static_cast<std::uint64_t>(1'700'000'000'000'000 + number * 10'000), 8);
    be(channel.size(), 4);
    be(data.size(), 4);
    out.write(channel.data(), static_cast<std::streamsize>(channel.size()));
    out.write(reinterpret_cast<const char*>(data.data()),
              static_cast<std::streamsize>(data.size()));
  };
  const std::string& state = names[transport::index_of(transport::Topic::kState)];
  const std::string& scene = names[transport::index_of(transport::Topic::kScene)];
  for (int i = 0; i < states; ++i) {
    const auto s = codec.encode(state_at(i));
    event(state, {s.data(), s.size()});
    if (i == 1 || i == 3) {  // SceneInfo after the first state, and repeated (once a second)
      const auto d = codec.encode(two_bodies("lcm"));
      event(scene, {d.data(), d.size()});
    }
    for (const auto& [after, command] : commands) {
      if (after != i) continue;
      const auto a = codec.encode(command);
      event(names[transport::index_of(transport::Topic::kAccepted)], {a.data(), a.size()});
    }
  }
}

TEST_F(RecordingFiles, LoadsAnLcmLoggerLog) {
  const std::string file = path("run.log");
  write_lcm_log(file, "bot", 6);
  const Recording r = load_recording(file, {});
  EXPECT_EQ(r.kind, "lcm-logger log");
  ASSERT_EQ(r.scenes.size(), 1u);  // repeated SceneInfo is one scene
  EXPECT_EQ(r.scenes[0], two_bodies("lcm"));
  ASSERT_EQ(r.states.size(), 6u);
  for (std::size_t i = 0; i < 6; ++i) {
    EXPECT_EQ(r.states[i].scene, 0u);
    StateFrame s = state_at(static_cast<std::int64_t>(i));
    s.stamp_ns = 0;
    EXPECT_EQ(zero_drifts(*r.frames[i]), encode_state(s, 1, {}, {}));
  }
  LoadLimits other;
  other.lcm_prefix = "other";
  other.lcm_prefix_given = true;
  EXPECT_NE(what_of_load(file, other).find("no SceneInfo"), std::string::npos);
}

TEST_F(RecordingFiles, AnLcmLoggerLogsAcceptedWrenchesAreShown) {
  const std::string file = path("push.log");
  // At tick 2 for 0.02 s: the steps 2 -> 4; at tick 0 for 0.03 s, logged before the first
  // SceneInfo (the log's dt is not known yet): the steps 0 -> 3.
  write_lcm_log(file, "bot", 8, {{2, wrench_at(2, 1, 0.02)}, {0, wrench_at(0, 2, 0.03, 1)}});
  const Recording r = load_recording(file, {});
  ASSERT_EQ(r.states.size(), 8u);
  EXPECT_EQ(shown_by_seq(r).at(1), ticks(0, 2, 4));
  EXPECT_EQ(shown_by_seq(r).at(2), ticks(0, 0, 3));
}

// ---- journals ----------------------------------------------------------------------------------

// Every body model, gravity and drag: states that a replay gets right only bit for bit.
const std::string kJournalScene = R"(
world { rate_hz: 200 publish_every: 3 gravity { z: -9.81 } limits { max_ttl: 10 } }
body { name: "puck" mass: 2 linear_drag: 0.3 }
body { name: "top" mass: 1 inertia { x: 1 y: 1 z: 2 } angular_velocity { x: 0.1 z: 5 } }
body { name: "brick" mass: 1 inertia { x: 1 y: 2 z: 3 } angular_velocity { x: 0.1 y: 3 } }
)";

// A session as rigidd's loop runs it and journals it (server/loop/loop.cpp, journal.cpp), without
// its threads: the loop's DrivenWorld takes wrenches and resets between ticks, a state is
// published every publish_every ticks, on the tick after a command and at tick 0 after a reset,
// and the journal gets each accepted command with its tick and each published state's hash, as
// the Journal writes them (accepted_command, the CommandRecord, the StateHash). `published` keeps
// every state the buses were given: what rigid-view must show, and nothing else.
class JournaledSession {
 public:
  JournaledSession(const std::string& path, std::size_t wrench_capacity)
      : scene_(scene::parse_scene(kJournalScene, "journal_view.pbtxt")),
        tick_dt_(1.0 / scene_.rate_hz),
        driven_(scene_.world, tick_dt_, scene_.substeps, wrench_capacity),
        writer_(path, false) {
    description = common::describe_scene(scene_, driven_.world());
    msgs::LogHeader& h = *record_.mutable_header();
    h.set_kind(msgs::LogHeader::JOURNAL);
    h.set_schema_version(common::kLogSchemaVersion);
    h.set_software_version(common::software_version());
    h.set_writer("view_playback_test");
    common::to_record(description, 0, *h.mutable_scene());
    h.set_integrator(description.integrator);
    h.set_rate_hz(scene_.rate_hz);
    h.set_scene_text(kJournalScene);
    h.set_mode("fast");
    h.set_wrench_capacity(wrench_capacity);
    writer_.append(record_);
    common::shape_state_frame(driven_.world(), frame_);
    publish();  // tick 0
  }

  void wrench(const common::Wrench& w) {
    ASSERT_EQ(driven_.apply(w), common::WrenchTable::Upsert::kInserted);
    common::JournalEntry e;
    e.tick = driven_.tick();
    e.what = w;
    command(e);
  }
  void reset() {
    common::JournalEntry e;
    e.tick = driven_.tick();
    e.what = common::Control{9, ++control_seq_, ControlKind::kReset, 0, 0};
    command(e);
    driven_.reset();
    hashed_tick_ = -1;
    new_command_ = false;
    publish();
  }
  void ticks(int n) {
    for (int i = 0; i < n; ++i) {
      driven_.step_tick();
      if (driven_.tick() % scene_.publish_every == 0 || new_command_) publish();
      new_command_ = false;
    }
  }
  void close() {
    record_.mutable_end();
    writer_.append(record_);
    writer_.close();
  }

  SceneDescription description;
  std::vector<StateFrame> published;

 private:
  void command(const common::JournalEntry& e) {
    common::to_record(common::accepted_command(e), 0, *record_.mutable_command());
    writer_.append(record_);
    new_command_ = true;
  }
  void publish() {
    const std::int64_t tick = driven_.tick();
    // sim_time as rigidd computes it (tick x tick_dt), to the bit.
    common::fill_state_frame(driven_.world(), tick, static_cast<double>(tick) * tick_dt_, frame_);
    if (tick == hashed_tick_) return;  // republished unchanged: hashed once
    published.push_back(frame_);
    msgs::StateHash& h = *record_.mutable_state_hash();
    h.set_tick(tick);
    h.set_hash(common::state_hash(frame_));
    writer_.append(record_);
    hashed_tick_ = tick;
  }

  scene::Scene scene_;
  double tick_dt_;
  common::DrivenWorld driven_;
  common::RecordWriter writer_;
  msgs::LogRecord record_;
  StateFrame frame_;
  std::int64_t hashed_tick_ = -1;
  std::int64_t control_seq_ = 0;
  bool new_command_ = false;
};

common::Wrench push_on(std::int32_t body, std::int64_t seq, double fx, double ttl) {
  common::Wrench w;
  w.source = 3;
  w.seq = seq;
  w.body = body;
  w.force = {fx, 0.5, -1};
  w.point = {0.1, -0.05, 0.2};  // off the centre of mass: a torque too
  w.force_frame = body % 2 ? rigid::Frame::kBody : rigid::Frame::kWorld;
  w.torque = {0, 0.2 * fx, 0};
  w.ttl = ttl;
  return w;
}

// rigid-sim --replay's reading of a journal, record by record, and its writing back.
std::vector<msgs::LogRecord> read_records(const std::string& path) {
  common::RecordReader reader(path);
  std::vector<msgs::LogRecord> all;
  msgs::LogRecord r;
  while (reader.next(r))
    all.push_back(r);
  return all;
}
void write_records(const std::string& path, const std::vector<msgs::LogRecord>& all) {
  common::RecordWriter w(path, true);
  for (const msgs::LogRecord& r : all)
    w.append(r);
  w.close();
}

class JournalFiles : public RecordingFiles {
 protected:
  void SetUp() override {
    RecordingFiles::SetUp();
    journal_ = path("run.journal");
    JournaledSession s(journal_, 64);
    s.ticks(40);
    s.wrench(push_on(0, 1, 4, 0.1));
    s.wrench(push_on(1, 2, -2, 0));  // 0: one tick
    s.ticks(31);
    s.wrench(push_on(2, 3, 1.5, 0.5));
    s.ticks(50);
    s.reset();  // the timeline carries on across it
    s.ticks(20);
    s.wrench(push_on(2, 4, -3, 0.05));
    s.ticks(62);
    s.close();
    description_ = s.description;
    live_ = s.published;
  }

  // The page's frame of a state rigidd published (stamp 0: see recording_source.hpp).
  static std::string page_frame(StateFrame s) {
    s.stamp_ns = 0;
    return encode_state(s, Recording::generation(0), {}, {});
  }
  // The loaded journal shows the first `n` states rigidd published, frame for frame.
  void expect_live_prefix(const Recording& r, std::size_t n) const {
    ASSERT_EQ(r.states.size(), n);
    ASSERT_EQ(r.frames.size(), n);
    ASSERT_LE(n, live_.size());
    for (std::size_t i = 0; i < n; ++i) {
      EXPECT_EQ(r.states[i].tick, live_[i].tick) << i;
      EXPECT_EQ(r.states[i].sim_time, live_[i].sim_time) << i;
      EXPECT_EQ(r.states[i].scene, 0u) << i;
      if (i > 0) {
        EXPECT_GE(r.states[i].position, r.states[i - 1].position) << i;
      }
      ASSERT_TRUE(r.frames[i]);
      EXPECT_EQ(zero_drifts(*r.frames[i]), page_frame(live_[i]))
          << "state " << i << ", tick " << live_[i].tick;
    }
  }

  std::string journal_;
  SceneDescription description_;
  std::vector<StateFrame> live_;
};

TEST_F(JournalFiles, PlaysEveryStateRigiddPublishedFrameForFrame) {
  // 0..121 every 3rd tick and after each command, 0 after the reset, then to tick 82.
  ASSERT_GT(live_.size(), 60u);
  const Recording r = load_recording(journal_, {});
  EXPECT_EQ(r.kind, "rigidd journal, replayed");
  EXPECT_TRUE(r.note.empty()) << r.note;
  ASSERT_EQ(r.scenes.size(), 1u);
  EXPECT_EQ(r.scenes[0], description_);
  expect_live_prefix(r, live_.size());
  // The states differ: the commands and the bodies' motion show in them.
  EXPECT_NE(*r.frames[1], *r.frames[2]);
  EXPECT_TRUE(r.stats.empty());  // a journal holds no Stats
}

TEST_F(JournalFiles, DriftIsTheIntegratorsAlonePushedBodiesIncluded) {
  // Four pushes change the three bodies' energy and momentum by their work: the loader retakes a
  // pushed body's reference while its push acts (drift.hpp), so what the frames carry for the
  // top and the brick (pushed, otherwise free under gravity) is the integrator's error, round-off
  // here, in every state. (The puck's linear drag takes energy all the time: work, not error.)
  const Recording r = load_recording(journal_, {});
  ASSERT_EQ(r.frames.size(), live_.size());
  ASSERT_EQ(description_.names[0], "puck");
  const std::int32_t puck = description_.ids[0];
  float worst = 0;
  for (std::size_t i = 0; i < r.frames.size(); ++i) {
    const auto [e, m] = drifts_of(*r.frames[i]);
    ASSERT_EQ(e.size(), live_[i].body_count());
    for (std::size_t k = 0; k < e.size(); ++k) {
      ASSERT_TRUE(std::isfinite(e[k]) && std::isfinite(m[k])) << "state " << i << " body " << k;
      if (live_[i].ids[k] != puck) worst = std::max({worst, e[k], m[k]});
    }
  }
  EXPECT_LT(worst, 1e-9f);
  // Without its pushes the tracker sees their work as drift (what the loader must not show).
  DriftTracker blind;
  blind.set_scene(description_);
  float seen = 0;
  for (const StateFrame& s : live_) {
    blind.update(s);
    for (std::size_t k = 0; k < s.body_count(); ++k)
      if (s.ids[k] != puck) seen = std::max({seen, blind.energy()[k], blind.momentum()[k]});
  }
  EXPECT_GT(seen, 1e-3f);
}

TEST_F(JournalFiles, ShowsEachJournaledWrenchWithTheStatesItsTicksProduced) {
  // The session's wrenches (SetUp), at 200 Hz: push 1 at tick 40 for 0.1 s (20 ticks), push 2 at
  // tick 40 for one tick, push 3 at tick 71 for 0.5 s (100 ticks, but rigidd was reset at tick
  // 121), then after the reset push 4 at tick 20 for 0.05 s (10 ticks). Only the states rigidd
  // published are in the file (every 3rd tick and after each command).
  struct Expected {
    std::int64_t seq;
    std::uint32_t stretch;
    std::int64_t from, last;
  };
  const std::vector<Expected> expected{
      {1, 0, 40, 60}, {2, 0, 40, 41}, {3, 0, 71, 121}, {4, 1, 20, 30}};
  const Recording r = load_recording(journal_, {});
  ASSERT_EQ(r.states.size(), live_.size());
  ASSERT_EQ(r.wrenches.all().size(), 4u);
  std::size_t shown = 0;
  for (std::size_t i = 0; i < r.states.size(); ++i) {
    std::vector<std::int64_t> want, got;
    for (const Expected& e : expected) {
      if (r.states[i].stretch == e.stretch && r.states[i].tick > e.from &&
          r.states[i].tick <= e.last)
        want.push_back(e.seq);
    }
    for (const std::size_t k : r.wrenches_at(i))
      got.push_back(r.wrenches.all()[k].command.seq);
    std::sort(got.begin(), got.end());
    EXPECT_EQ(got, want) << "state " << i << ", tick " << r.states[i].tick << ", stretch "
                         << r.states[i].stretch;
    shown += got.size();
  }
  EXPECT_GT(shown, 20u);
  EXPECT_EQ(r.states.back().stretch, 1u);
}

TEST_F(JournalFiles, ItsSceneIsDescribedFromTheSceneFileWhenTheHeaderHasNone) {
  std::vector<msgs::LogRecord> all = read_records(journal_);
  all.front().mutable_header()->clear_scene();
  const std::string file = path("no_scene_info.journal");
  write_records(file, all);
  const Recording r = load_recording(file, {});
  ASSERT_EQ(r.scenes.size(), 1u);
  SceneDescription expected = description_;
  expected.scene_name = file + ":scene";  // rigidd's name for it (its path) is not in the file
  EXPECT_EQ(r.scenes[0], expected);
  expect_live_prefix(r, live_.size());
}

TEST_F(JournalFiles, AHashThatDoesNotMatchRefusesTheWholeJournal) {
  std::vector<msgs::LogRecord> all = read_records(journal_);
  std::size_t hashes = 0;
  std::int64_t tick = -1;
  for (msgs::LogRecord& rec : all) {
    if (rec.has_state_hash() && ++hashes == 20) {
      rec.mutable_state_hash()->set_hash(rec.state_hash().hash() ^ 1);  // one bit
      tick = rec.state_hash().tick();
    }
  }
  ASSERT_GE(tick, 0);
  const std::string file = path("bad_hash.journal");
  write_records(file, all);
  const std::string why = what_of_load(file);
  EXPECT_EQ(why.find('\n'), std::string::npos) << why;
  EXPECT_EQ(why.rfind(file + ": the replay does not reproduce it: DIVERGED at tick " +
                          std::to_string(tick) + " (state hash mismatch)",
                      0),
            0u)
      << why;
}

TEST_F(JournalFiles, ACommandThatWasNotRigiddsRefusesTheWholeJournal) {
  std::vector<msgs::LogRecord> all = read_records(journal_);
  msgs::LogRecord* first_command = nullptr;
  for (msgs::LogRecord& rec : all) {
    if (rec.has_command()) {
      first_command = &rec;
      break;
    }
  }
  ASSERT_NE(first_command, nullptr);
  AcceptedCommand a;
  common::from_record(first_command->command(), a);
  a.force[0] += 1e-9;  // a whisker: the next state's hash differs all the same
  common::to_record(a, 0, *first_command->mutable_command());
  const std::string file = path("changed.journal");
  write_records(file, all);
  const std::string why = what_of_load(file);
  EXPECT_EQ(why.find('\n'), std::string::npos) << why;
  EXPECT_EQ(why.rfind(file + ": the replay does not reproduce it: DIVERGED at tick ", 0), 0u)
      << why;
}

TEST_F(JournalFiles, ACutJournalPlaysItsVerifiedStatesAndSaysWhere) {
  std::vector<msgs::LogRecord> all = read_records(journal_);
  std::size_t hashes = 0;
  std::size_t keep = 0;  // records up to and including the 30th state hash
  for (std::size_t i = 0; i < all.size() && hashes < 30; ++i) {
    if (all[i].has_state_hash()) ++hashes;
    keep = i + 1;
  }
  all.resize(keep);
  const std::string clean_cut = path("cut.journal");
  write_records(clean_cut, all);
  // A few bytes of a record after the last whole one: a damaged tail, as rigidd killed mid-write.
  const char partial[] = {0x10, 0x00, 0x00};
  std::ofstream(clean_cut, std::ios::binary | std::ios::app).write(partial, sizeof partial);
  const Recording r = load_recording(clean_cut, {});
  expect_live_prefix(r, 30);
  EXPECT_NE(r.note.find("played up to a damaged tail"), std::string::npos) << r.note;
}

TEST_F(JournalFiles, AGapPlaysTheStatesVerifiedBeforeIt) {
  std::vector<msgs::LogRecord> all = read_records(journal_);
  std::size_t hashes = 0;
  std::size_t at = 0;
  for (std::size_t i = 0; i < all.size(); ++i) {
    if (all[i].has_state_hash() && ++hashes == 25) {
      at = i + 1;
      break;
    }
  }
  ASSERT_GT(at, 0u);
  msgs::LogRecord gap;
  gap.mutable_gap()->set_dropped(7);
  gap.mutable_gap()->set_tick(live_[25].tick);
  all.insert(all.begin() + static_cast<std::ptrdiff_t>(at), gap);
  const std::string file = path("gap.journal");
  write_records(file, all);
  const Recording r = load_recording(file, {});
  expect_live_prefix(r, 25);
  EXPECT_NE(r.note.find("rigidd lost 7 journal entries"), std::string::npos) << r.note;
}

TEST_F(JournalFiles, TheMemoryLimitHoldsForJournalsToo) {
  const Recording all = load_recording(journal_, {});
  LoadLimits limits;
  limits.max_bytes = all.bytes - 1;
  const std::string why = what_of_load(journal_, limits);
  // (The states come first, the commands of the journal after them: they meet the limit.)
  EXPECT_EQ(why.rfind(journal_ + ": its states and accepted commands need more than 1 MiB", 0), 0u)
      << why;
  limits.max_bytes = all.bytes;
  EXPECT_EQ(what_of_load(journal_, limits), "loaded");
}

TEST_F(JournalFiles, AJournalThatCannotBeReplayedIsOneLineNamingIt) {
  std::vector<msgs::LogRecord> all = read_records(journal_);
  all.front().mutable_header()->set_scene_text("body { name: \"x\" mass: -1 }\n");
  const std::string file = path("bad_scene.journal");
  write_records(file, all);
  const std::string why = what_of_load(file);
  EXPECT_EQ(why.find('\n'), std::string::npos) << why;
  EXPECT_EQ(why.rfind(file + ": cannot replay it: ", 0), 0u) << why;
}

// ---- the playback clock ------------------------------------------------------------------------

std::vector<RecordedState> eleven_states() {  // t = 0, 0.1, ..., 1.0 s at ticks 100, 110, ...
  std::vector<RecordedState> s;
  for (int i = 0; i <= 10; ++i)
    s.push_back(RecordedState{100 + 10 * i, 0.1 * i, 0.1 * i, 0});
  return s;
}

TEST(ViewPlaybackClock, PlaysPausesAndStopsAtTheEnd) {
  const auto states = eleven_states();
  PlaybackClock c(states);
  const PlaybackClock::Clock::time_point t0{};
  EXPECT_FALSE(c.playing());
  EXPECT_EQ(c.current(t0 + 5s), 0u);  // paused at the start until play
  c.play(t0);
  EXPECT_EQ(c.current(t0 + 350ms), 3u);
  c.pause(t0 + 350ms);
  EXPECT_EQ(c.current(t0 + 10s), 3u);  // pause holds
  c.play(t0 + 10s);
  EXPECT_EQ(c.current(t0 + 10s + 250ms), 5u);  // on from 0.3 s
  EXPECT_EQ(c.current(t0 + 20s), 10u);
  EXPECT_FALSE(c.playing());  // the end pauses there
  EXPECT_EQ(c.current(t0 + 30s), 10u);
  c.play(t0 + 30s);  // from the start again
  EXPECT_EQ(c.current(t0 + 30s), 0u);
}

TEST(ViewPlaybackClock, SpeedScalesTheWallClock) {
  const auto states = eleven_states();
  PlaybackClock c(states);
  const PlaybackClock::Clock::time_point t0{};
  c.set_speed(4, t0);
  c.play(t0);
  EXPECT_EQ(c.current(t0 + 130ms), 5u);  // 0.52 s
  c.set_speed(0.5, t0 + 130ms);          // no jump when the speed changes
  EXPECT_EQ(c.current(t0 + 130ms), 5u);
  EXPECT_EQ(c.current(t0 + 130ms + 200ms), 6u);  // 0.52 + 0.1
  EXPECT_NEAR(c.position(t0 + 130ms + 200ms), 0.62, 1e-9);
}

TEST(ViewPlaybackClock, SeeksByTimeAndByTick) {
  const auto states = eleven_states();
  PlaybackClock c(states);
  const PlaybackClock::Clock::time_point t0{};
  EXPECT_EQ(c.seek_time(0.54, t0), 5u);  // the nearest state
  EXPECT_EQ(c.seek_time(0.56, t0), 6u);
  EXPECT_EQ(c.seek_time(0.7 - 1e-12, t0), 7u);  // a time rounded below a state's still finds it
  EXPECT_EQ(c.current(t0 + 1s), 7u);            // paused: stays there
  EXPECT_EQ(c.seek_time(-3, t0), 0u);
  EXPECT_EQ(c.seek_time(99, t0), 10u);
  EXPECT_EQ(c.seek_tick(170, t0), 7u);
  EXPECT_EQ(c.current(t0), 7u);
  EXPECT_EQ(c.seek_tick(174, t0), 7u);  // none has it: the nearest
  EXPECT_EQ(c.seek_tick(0, t0), 0u);
  c.play(t0);
  EXPECT_EQ(c.seek_tick(120, t0 + 1ms), 2u);
  EXPECT_EQ(c.current(t0 + 1ms + 100ms), 3u);  // playing on from the state sought
  EXPECT_TRUE(c.playing());
}

TEST(ViewPlaybackClock, ShowsExactlyTheStateSoughtAmongEqualPositions) {
  std::vector<RecordedState> s{
      {5, 0.5, 0.5, 0}, {6, 0.6, 0.6, 0}, {0, 0, 0.6, 0}, {1, 0.1, 0.7, 0}};
  PlaybackClock c(s);
  const PlaybackClock::Clock::time_point t0{};
  EXPECT_EQ(c.seek_tick(6, t0), 1u);  // shares its position with the reset state after it
  EXPECT_EQ(c.current(t0), 1u);
  EXPECT_EQ(c.seek_tick(0, t0), 2u);
}

}  // namespace
}  // namespace rigid::view
