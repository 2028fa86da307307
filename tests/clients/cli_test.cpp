// The tools' command lines, without a network: what each accepts, and that every refusal is one
// line naming the argument and its value with exit status 2 before any bus is opened.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "attitude_options.hpp"
#include "ctl/ctl_options.hpp"
#include "ctl/push_request.hpp"
#include "record/record_options.hpp"
#include "rigidd_process.hpp"

namespace rigid::clients {
namespace {

using rigidd::testing::Completed;
using rigidd::testing::count_lines;
using rigidd::testing::run_program_to_exit;

std::vector<std::string_view> view(const std::vector<std::string>& args) {
  return {args.begin(), args.end()};
}

ctl::CtlOptions ctl_parse(const std::vector<std::string>& args) {
  const auto v = view(args);
  return ctl::parse_options(v);
}

TEST(RigidctlOptions, CommandsAndTheirArguments) {
  const ctl::CtlOptions push =
      ctl_parse({"push", "brick", "--force", "1,-2,3e-1", "--at=0.5,0,0", "--frame", "body",
                 "--for", "2.5", "--transport", "lcm", "--prefix", "lab", "--timeout", "0.5"});
  EXPECT_EQ(push.command, ctl::Command::kPush);
  EXPECT_EQ(push.body, "brick");
  EXPECT_EQ(push.force, (rigid::Vec3{1, -2, 0.3}));
  EXPECT_EQ(push.point, (rigid::Vec3{0.5, 0, 0}));
  EXPECT_EQ(push.frame, rigid::Frame::kBody);
  EXPECT_EQ(push.for_seconds, 2.5);
  EXPECT_EQ(push.torque, (rigid::Vec3{}));
  EXPECT_FALSE(ctl_parse({"push", "brick", "--torque", "0,0,1"}).for_seconds);
  EXPECT_EQ(push.bus.bus, rigid::Bus::kLcm);
  EXPECT_EQ(push.bus.prefix, "lab");
  EXPECT_EQ(push.timeout, std::chrono::milliseconds(500));

  const ctl::CtlOptions echo = ctl_parse({"echo", "a", "b", "--csv", "--count", "3"});
  EXPECT_EQ(echo.bodies, (std::vector<std::string>{"a", "b"}));
  EXPECT_TRUE(echo.csv);
  EXPECT_EQ(echo.count, 3);
  EXPECT_EQ(ctl_parse({"step", "10"}).steps, 10);
  EXPECT_EQ(ctl_parse({"rate", "0.5"}).rtf, 0.5);
  EXPECT_EQ(ctl_parse({"--dds-domain", "7", "reset"}).bus.dds_domain, 7u);
  EXPECT_TRUE(ctl_parse({"--help"}).help);
}

TEST(RigidctlOptions, RefusalsNameTheArgumentAndItsValue) {
  const struct {
    std::vector<std::string> args;
    std::string message;
  } cases[] = {
      {{}, "missing the command"},
      {{"frobnicate"}, "unknown command 'frobnicate'"},
      {{"step"}, "step: missing the number of ticks"},
      {{"step", "0"}, "step: expected an integer >= 1, got '0'"},
      {{"step", "1", "2"}, "step: unexpected argument '2'"},
      {{"rate", "0"}, "rate: expected a real-time factor > 0 and <= 1000, got '0'"},
      {{"rate", "1001"}, "rate: expected a real-time factor > 0 and <= 1000, got '1001'"},
      {{"push", "box"}, "push: missing --force fx,fy,fz or --torque tx,ty,tz"},
      {{"push", "box", "--torque", "1,2"}, "--torque: expected three numbers x,y,z, got '1,2'"},
      {{"push", "box", "--force", "1,2"}, "--force: expected three numbers x,y,z, got '1,2'"},
      {{"push", "box", "--force", "1,2,nan"}, "--force: expected three numbers x,y,z, got"},
      {{"push", "box", "--force", "1,2,3", "--frame", "local"},
       "--frame: expected body or world, got 'local'"},
      {{"push", "box", "--force", "1,2,3", "--for", "-1"},
       "--for: expected a duration in seconds >= 0, got '-1'"},
      {{"pause", "--csv"}, "unknown option '--csv' for pause"},
      {{"pause", "--transport", "zmq"}, "--transport: expected dds or lcm, got 'zmq'"},
      {{"pause", "--prefix", "a-b"}, "--prefix: expected letters, digits and '_' only, got 'a-b'"},
      {{"pause", "--dds-domain", "300"}, "--dds-domain: expected an integer 0 .. 232, got '300'"},
      {{"pause", "--lcm-url", "x"}, "--lcm-url: expected an LCM URL"},
      {{"pause", "--timeout", "0"}, "--timeout: expected a time in seconds > 0, got '0'"},
      {{"pause", "--timeout"}, "--timeout needs a value"},
      {{"echo", "--rate", "fast"}, "--rate: expected a rate in Hz > 0, got 'fast'"},
  };
  for (const auto& c : cases) {
    try {
      ctl_parse(c.args);
      ADD_FAILURE() << "accepted: " << (c.args.empty() ? "" : c.args[0]);
    } catch (const UsageError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(c.message, 0), 0u) << e.what();
    }
  }
}

// rigidctl push against the running scene (push_request.hpp): what rigidd would refuse is refused
// with its reason before sending; without --for a push lasts 1 s (or the scene's max_ttl if less),
// and the answer says what it amounts to.
rigid::SceneDescription push_scene(double max_ttl) {
  rigid::SceneDescription s;
  s.dt = 0.001;
  s.max_force = 100;
  s.max_torque = 50;
  s.max_ttl = max_ttl;
  s.ids = {0, 1};
  s.names = {"puck", "brick"};
  s.masses = {2.0, 8.0};
  return s;
}

TEST(RigidctlPush, TheScenesLimitsAreCheckedAsRigiddWouldAndTheDefaultLastsOneSecond) {
  const rigid::SceneDescription scene = push_scene(5);
  const ctl::PushRequest ok =
      ctl::make_push(ctl_parse({"push", "brick", "--force", "8,0,0"}), scene, 1);
  EXPECT_TRUE(ok.refusal.empty()) << ok.refusal;
  EXPECT_EQ(ok.wrench.ttl, 1.0);
  EXPECT_EQ(ok.wrench.body_name, "brick");
  EXPECT_EQ(ctl::push_summary(ok, ctl_parse({"push", "brick", "--force", "8,0,0"}), scene),
            "for 1 s (default; --for S): impulse 8 N s, |dv| 1 m/s on its 8 kg");
  // A scene whose max_ttl is below the default: the push lasts max_ttl.
  EXPECT_EQ(ctl::make_push(ctl_parse({"push", "puck", "--force", "1,0,0"}), push_scene(0.25), 0)
                .wrench.ttl,
            0.25);
  // Torque, in the frame --frame names, alone or with a force.
  const ctl::CtlOptions twist =
      ctl_parse({"push", "puck", "--torque", "0,0,3", "--frame", "body", "--for", "0.5"});
  const ctl::PushRequest t = ctl::make_push(twist, scene, 0);
  EXPECT_EQ(t.wrench.torque, (rigid::Vec3{0, 0, 3}));
  EXPECT_EQ(t.wrench.torque_frame, rigid::Frame::kBody);
  EXPECT_EQ(t.wrench.force_frame, rigid::Frame::kBody);
  EXPECT_EQ(ctl::push_summary(t, twist, scene), "for 0.5 s: angular impulse 1.5 N m s");
  const ctl::CtlOptions tick = ctl_parse({"push", "puck", "--force", "2,0,0", "--for", "0"});
  EXPECT_EQ(ctl::push_summary(ctl::make_push(tick, scene, 0), tick, scene),
            "for one tick (1 ms; --for S pushes longer): impulse 0.002 N s, |dv| 0.001 m/s on "
            "its 2 kg");
  const struct {
    std::vector<std::string> args;
    std::string refusal;
  } refused[] = {
      {{"push", "puck", "--force", "0,0,101"},
       "--force: |f| = 101 N is above the scene's max_force of 100 N"},
      {{"push", "puck", "--torque", "51,0,0"},
       "--torque: |t| = 51 N m is above the scene's max_torque of 50 N m"},
      {{"push", "puck", "--force", "0,0,60", "--at", "1,0,0"},
       "--at: |point x force| = 60 N m is above the scene's max_torque of 50 N m"},
      {{"push", "puck", "--force", "1,0,0", "--for", "6"},
       "--for 6 s is above the scene's max_ttl of 5 s"},
  };
  for (const auto& c : refused)
    EXPECT_EQ(ctl::make_push(ctl_parse(c.args), scene, 0).refusal, c.refusal) << c.refusal;
}

TEST(RigidRecordOptions, CommandsAndRefusals) {
  auto parse = [](const std::vector<std::string>& args) {
    const auto v = view(args);
    return record::parse_options(v);
  };
  const record::RecordOptions r =
      parse({"record", "out.rlog", "--duration", "2", "--force", "--transport", "lcm"});
  EXPECT_EQ(r.command, record::Command::kRecord);
  EXPECT_EQ(r.file, "out.rlog");
  EXPECT_EQ(r.duration, 2.0);
  EXPECT_TRUE(r.force);
  const record::RecordOptions e = parse({"export", "a.log", "--csv", "a.csv", "--prefix", "p"});
  EXPECT_EQ(e.csv, "a.csv");
  EXPECT_TRUE(e.bus_prefix_given);
  EXPECT_EQ(e.bus.prefix, "p");
  const record::RecordOptions m = parse({"export", "a.rlog", "--mcap", "a.mcap", "-f"});
  EXPECT_EQ(m.mcap, "a.mcap");
  EXPECT_TRUE(m.csv.empty());
  EXPECT_TRUE(m.force);
  EXPECT_EQ(parse({"play", "a.rlog", "--speed", "4"}).speed, 4.0);
  const record::RecordOptions d =
      parse({"record", "o.rlog", "--every", "10", "--compress", "none"});
  EXPECT_EQ(d.every, 10);
  EXPECT_FALSE(d.compress);
  EXPECT_TRUE(parse({"record", "o.rlog"}).compress);
  EXPECT_EQ(parse({"record", "o.rlog"}).every, 1);
  EXPECT_TRUE(parse({"record", "-f", "o.rlog"}).force);
  const struct {
    std::vector<std::string> args;
    std::string message;
  } cases[] = {
      {{"record"}, "record: missing the output file"},
      {{"export", "a.rlog"}, "export: missing --csv OUT or --mcap OUT"},
      {{"export", "a.rlog", "--csv", "o", "--mcap", "o"}, "export: --csv and --mcap name the same"},
      {{"export", "a.rlog", "--mcap", ""}, "--mcap: expected a file name, got ''"},
      {{"info", "a", "b"}, "info: unexpected argument 'b'"},
      {{"info", "a", "--duration", "1"}, "unknown option '--duration' for info"},
      {{"play", "a", "--speed", "0"}, "--speed: expected a speed factor > 0, got '0'"},
      {{"record", "a", "--duration", "x"}, "--duration: expected a duration in seconds > 0"},
      {{"dump", "a"}, "unknown command 'dump'"},
      {{"record", "a", "--every", "0"}, "--every: expected an integer >= 1, got '0'"},
      {{"record", "a", "--compress", "lz4"}, "--compress: expected zstd or none, got 'lz4'"},
      {{"export", "a", "--csv", "b", "--every", "2"}, "unknown option '--every' for export"},
  };
  for (const auto& c : cases) {
    try {
      parse(c.args);
      ADD_FAILURE() << "accepted: " << c.args[0];
    } catch (const UsageError& err) {
      EXPECT_EQ(std::string(err.what()).rfind(c.message, 0), 0u) << err.what();
    }
  }
}

TEST(RigidAttitudeOptions, ValuesAndRefusals) {
  const std::vector<std::string> args{"craft", "--target-rpy", "10,0,-5", "--max-thrust",
                                      "2",     "--duration",   "3",       "--exit-when-settled"};
  const auto v = view(args);
  const controllers::AttitudeOptions o = controllers::parse_options(v);
  EXPECT_EQ(o.body, "craft");
  EXPECT_EQ(o.target_rpy_deg, (rigid::Vec3{10, 0, -5}));
  EXPECT_EQ(o.max_thrust, 2.0);
  EXPECT_EQ(o.duration, 3.0);
  EXPECT_TRUE(o.exit_when_settled);
  const std::vector<std::string> bad{"--max-thrust", "-1"};
  const auto bv = view(bad);
  EXPECT_THROW(controllers::parse_options(bv), UsageError);
}

// As processes: one line on stderr, exit status 2, nothing on stdout; --help exits 0.
TEST(ToolsAsProcesses, BadCommandLinesExit2WithOneLineAndHelpExits0) {
  const struct {
    const char* program;
    std::vector<std::string> args;
    std::string line;
  } cases[] = {
      {RIGIDCTL_EXE, {"step", "-3"}, "rigidctl: step: expected an integer >= 1, got '-3'"},
      {RIGIDCTL_EXE, {"push", "b", "--force", "1"}, "rigidctl: --force: expected three numbers"},
      {RIGID_RECORD_EXE, {"export", "x"}, "rigid-record: export: missing --csv OUT or --mcap OUT"},
      {RIGID_ATTITUDE_EXE, {"--rate", "0"}, "rigid-attitude: --rate: expected a rate in Hz > 0"},
      {RIGID_SIM_EXE,
       {"--replay", "j", "--dt", "1e-3"},
       "rigid-sim: --dt cannot be combined with --replay"},
  };
  for (const auto& c : cases) {
    const Completed r = run_program_to_exit(c.program, c.args);
    EXPECT_EQ(r.exit_code, 2) << c.program << ' ' << r.err;
    EXPECT_EQ(count_lines(r.err), 1) << r.err;
    EXPECT_EQ(r.err.rfind(c.line, 0), 0u) << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
  }
  for (const char* program : {RIGIDCTL_EXE, RIGID_RECORD_EXE, RIGID_ATTITUDE_EXE}) {
    const Completed r = run_program_to_exit(program, {"--help"});
    EXPECT_EQ(r.exit_code, 0) << program;
    EXPECT_NE(r.out.find("Usage:"), std::string::npos) << program;
    EXPECT_NE(r.out.find("Exit status"), std::string::npos) << program;
  }
}

TEST(ToolsAsProcesses, AMissingOrForeignFileIsOneLineAndExit1) {
  const Completed missing = run_program_to_exit(RIGID_RECORD_EXE, {"info", "/nonexistent.rlog"});
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_EQ(missing.err,
            "rigid-record: /nonexistent.rlog: cannot open: No such file or directory\n");
  const Completed foreign = run_program_to_exit(RIGID_SIM_EXE, {"--replay", RIGIDCTL_EXE});
  EXPECT_EQ(foreign.exit_code, 1);
  EXPECT_NE(foreign.err.find("not a rigid log file"), std::string::npos) << foreign.err;
}

TEST(ToolsAsProcesses, RigiddRefusesToOverwriteAJournalWithExit1) {
  const std::string path = std::filesystem::temp_directory_path() /
                           ("rigid_cli_test_journal_" + std::to_string(::getpid()));
  std::ofstream(path) << "an earlier incident";
  const Completed r = rigidd::testing::run_to_exit(
      {"--scene", std::string(RIGIDD_TEST_SCENES) + "/probe.pbtxt", "--journal", path});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.err, "rigidd: " + path + ": exists (remove it or choose another name)\n");
  std::ifstream in(path);
  std::string kept;
  std::getline(in, kept);
  EXPECT_EQ(kept, "an earlier incident");
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace rigid::clients
