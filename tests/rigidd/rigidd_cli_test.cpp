// rigidd's command line and scene errors, as a process: one line on stderr and exit status 2
// before anything runs (no bus is opened, so these need no network); --check and --help.
#include <gtest/gtest.h>
#include <sched.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "rigidd_process.hpp"

namespace rigid::rigidd::testing {
namespace {

const std::string kScenes = RIGIDD_TEST_SCENES;

TEST(RigiddCli, BadSceneGivesFileLineColumnAndExit2) {
  const std::string path = kScenes + "/bad_mass.pbtxt";
  const Completed r = run_to_exit({"--scene", path});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_EQ(r.err.rfind(path + ":5:3: ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find("mass"), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty());
}

TEST(RigiddCli, MissingSceneExits2) {
  const Completed r = run_to_exit({"--scene", kScenes + "/nope.pbtxt"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("nope.pbtxt: cannot open"), std::string::npos) << r.err;
}

TEST(RigiddCli, BadOptionsExit2WithOneLineNamingTheOptionAndValue) {
  const struct {
    std::vector<std::string> args;
    std::string expected;
  } cases[] = {
      {{"--mode", "slow"}, "--mode: expected realtime, fast or lockstep, got 'slow'"},
      {{"--transport", "dds,zmq"},
       "--transport: expected a comma-separated list of dds and lcm, "
       "got 'dds,zmq'"},
      {{"--transport="}, "--transport: expected"},
      {{"--dds-domain", "233"}, "--dds-domain: expected an integer 0 .. 232, got '233'"},
      {{"--dds-domain", "-1"}, "--dds-domain: expected an integer 0 .. 232, got '-1'"},
      {{"--prefix", "a b"}, "--prefix: expected letters, digits and '_' only, got 'a b'"},
      {{"--lcm-url", "nowhere"}, "--lcm-url: expected an LCM URL"},
      {{"--spin-us", "-5"}, "--spin-us: expected microseconds 0 .. 1000000, got '-5'"},
      {{"--threads", "-1"}, "--threads: expected 0 (every CPU) .. 256, got '-1'"},
      {{"--threads", "257"}, "--threads: expected 0 (every CPU) .. 256, got '257'"},
      {{"--threads=two"}, "--threads: expected 0 (every CPU) .. 256, got 'two'"},
      {{"--threads", "3x"}, "--threads: expected 0 (every CPU) .. 256, got '3x'"},
      {{"--threads"}, "--threads needs a value"},
      {{"--frobnicate"}, "unknown option '--frobnicate'"},
      {{"--scene"}, "--scene needs a value"},
      {{"scene.pbtxt"}, "unexpected argument 'scene.pbtxt'"},
  };
  for (const auto& c : cases) {
    const Completed r = run_to_exit(c.args);
    EXPECT_EQ(r.exit_code, 2) << c.args[0];
    EXPECT_EQ(count_lines(r.err), 1) << r.err;
    EXPECT_EQ(r.err.rfind("rigidd: " + c.expected, 0), 0u) << r.err;
  }
}

TEST(RigiddCli, CheckValidatesAndExits0) {
  const Completed r = run_to_exit({"--check", "--scene", kScenes + "/probe.pbtxt"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("rigidd: ok: "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("2 bodies, 1000 Hz"), std::string::npos) << r.out;
  // --check still refuses a bad scene.
  EXPECT_EQ(run_to_exit({"--check", "--scene", kScenes + "/bad_mass.pbtxt"}).exit_code, 2);
}

// --threads overrides the scene's world { threads }; without either, rigidd takes the CPUs it may
// use minus one (at least 1), which --check reports.
TEST(RigiddCli, ThreadsComeFromTheOptionElseTheSceneElseTheCpus) {
  const std::string probe = kScenes + "/probe.pbtxt";
  cpu_set_t set;
  CPU_ZERO(&set);
  ASSERT_EQ(sched_getaffinity(0, sizeof set, &set), 0);
  const int expected_default = std::max(1, CPU_COUNT(&set) - 1);

  Completed r = run_to_exit({"--check", "--scene", probe});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find(std::to_string(expected_default) + " physics thread(s))"), std::string::npos)
      << r.out;
  r = run_to_exit({"--check", "--threads", "3", "--scene", probe});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("3 physics thread(s) (--threads)"), std::string::npos) << r.out;
  r = run_to_exit({"--check", "--threads=0", "--scene", probe});
  EXPECT_NE(r.out.find("a physics thread per CPU (--threads)"), std::string::npos) << r.out;

  // A scene that names its threads: used without --threads, overridden by it.
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("rigidd_cli_threads_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  const std::string scene = (dir / "threads.pbtxt").string();
  {
    std::ifstream in(probe);
    std::ostringstream text;
    text << in.rdbuf();
    std::string t = text.str();
    const std::size_t world = t.find("world {");
    ASSERT_NE(world, std::string::npos);
    t.insert(world + 7, "\n  threads: 5\n");
    std::ofstream(scene) << t;
  }
  r = run_to_exit({"--check", "--scene", scene});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("5 physics thread(s) (scene)"), std::string::npos) << r.out;
  r = run_to_exit({"--check", "--scene", scene, "--threads", "2"});
  EXPECT_NE(r.out.find("2 physics thread(s) (--threads)"), std::string::npos) << r.out;
  std::filesystem::remove_all(dir);
}

TEST(RigiddCli, DefaultSceneIsFoundFromOutsideTheSourceTree) {
  // ctest runs this in the build directory, which has no config/: the source tree's is used.
  const Completed r = run_to_exit({"--check"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find(std::string(RIGID_SOURCE_DIR) + "/config/scenes/default.pbtxt"),
            std::string::npos)
      << r.out;
}

TEST(RigiddCli, Help) {
  const Completed r = run_to_exit({"--help"});
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("Usage: rigidd"), std::string::npos);
  EXPECT_TRUE(r.err.empty());
}

}  // namespace
}  // namespace rigid::rigidd::testing
