// rigid-sim as a process: exit codes, one-line errors on stderr, and the CSV it leaves behind.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "test_dir.hpp"

namespace rigid::sim {
namespace {

namespace fs = std::filesystem;
using testing::read_file;
using testing::TestDir;
using testing::write_file;

struct Result {
  int status = -1;
  std::string out, err;
};

// Runs rigid-sim with the given (shell-quoted) arguments.
Result run_sim(const TestDir& dir, const std::string& args) {
  const std::string out = dir.file("stdout"), err = dir.file("stderr");
  const std::string command =
      std::string("'") + RIGID_SIM_EXE + "' " + args + " >'" + out + "' 2>'" + err + "'";
  const int raw = std::system(command.c_str());
  Result r;
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  r.out = read_file(out);
  r.err = read_file(err);
  return r;
}

std::string scene(const std::string& name) {
  return std::string(RIGID_SCENES_DIR) + "/" + name;
}

int count_lines(const std::string& s) {
  int n = 0;
  for (char c : s)
    n += c == '\n';
  return n;
}

TEST(SimProcess, BadSceneExitsWith2AndOneLine) {
  const TestDir dir;
  const std::string path = dir.file("bad.pbtxt");
  write_file(path, "body {\n  name: \"a\"\n  mass: -1\n}\n");
  const std::string csv = dir.file("out.csv");
  const Result r = run_sim(dir, "'" + path + "' --csv '" + csv + "'");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_EQ(r.err.rfind(path + ":3:3: ", 0), 0u) << r.err;
  EXPECT_FALSE(fs::exists(csv));
  EXPECT_FALSE(fs::exists(csv + ".tmp"));
}

TEST(SimProcess, MissingSceneExitsWith2) {
  const TestDir dir;
  const Result r = run_sim(dir, "'" + dir.file("nope.pbtxt") + "'");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("nope.pbtxt: cannot open"), std::string::npos) << r.err;
}

TEST(SimProcess, BadArgumentExitsWith2) {
  const TestDir dir;
  const Result r = run_sim(dir, "'" + scene("racket.pbtxt") + "' --duration soon");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("--duration"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("'soon'"), std::string::npos) << r.err;
}

TEST(SimProcess, HelpAndListIntegrators) {
  const TestDir dir;
  Result r = run_sim(dir, "--help");
  EXPECT_EQ(r.status, 0);
  EXPECT_NE(r.out.find("Usage: rigid-sim"), std::string::npos);
  r = run_sim(dir, "--list-integrators");
  EXPECT_EQ(r.status, 0);
  EXPECT_NE(r.out.find("* "), std::string::npos) << r.out;
}

TEST(SimProcess, RunWritesCsvAndSummary) {
  const TestDir dir;
  const std::string csv = dir.file("racket.csv");
  const Result r =
      run_sim(dir, "'" + scene("racket.pbtxt") + "' --duration 0.5 --csv '" + csv + "'");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;
  EXPECT_NE(r.out.find("racket"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("ns per body-step"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(csv + ".tmp"));
  // publish_every 1 at 1 kHz: t = 0 and 500 ticks, one body.
  EXPECT_EQ(count_lines(read_file(csv)), 1 + 501);
}

TEST(SimProcess, UnwritableCsvExitsWith1AndLeavesNothing) {
  const TestDir dir;
  const std::string csv = dir.file("missing/out.csv");
  const Result r =
      run_sim(dir, "'" + scene("racket.pbtxt") + "' --duration 0.01 --csv '" + csv + "'");
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find(csv + ".tmp"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(csv));
}

// The contacts scene (config/scenes/contacts.pbtxt) with --contacts-csv: a row per event, as many
// as the summary says, the header first, each row's tick the one whose step holds its time, every
// body named and every event on the ground or the ramp; the block slides down the ramp and off it
// (its last events on the ground), and the lively ball rests on the ground. --contacts-csv equal
// to --csv is refused.
TEST(SimProcess, TheContactsSceneWritesEveryContactEventToItsCsv) {
  const TestDir dir;
  const std::string csv = dir.file("contacts.csv");
  const Result r =
      run_sim(dir, "'" + scene("contacts.pbtxt") + "' --duration 8 --contacts-csv '" + csv + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string text = read_file(csv);
  ASSERT_EQ(text.rfind("tick,t,kind,body,part,px,py,pz,nx,ny,nz,jx,jy,jz\n", 0), 0u);
  const int rows = count_lines(text) - 1;
  EXPECT_GT(rows, 100);
  EXPECT_NE(r.out.find("contacts csv: " + csv + ", " + std::to_string(rows) + " events"),
            std::string::npos)
      << r.out;
  std::istringstream in(text);
  std::string line;
  std::getline(in, line);
  std::set<std::string> bodies, parts;
  std::string block_last_part, bouncer_last_kind;
  while (std::getline(in, line)) {
    std::vector<std::string> f;
    std::istringstream fields(line);
    for (std::string x; std::getline(fields, x, ',');)
      f.push_back(x);
    ASSERT_EQ(f.size(), 14u) << line;
    const long long tick = std::stoll(f[0]);
    const double t = std::stod(f[1]);
    EXPECT_GT(t, static_cast<double>(tick - 1) * 1e-3 - 1e-12) << line;
    EXPECT_LE(t, static_cast<double>(tick) * 1e-3 + 1e-12) << line;
    bodies.insert(f[3]);
    parts.insert(f[4]);
    EXPECT_EQ(f[4].empty(), f[2] == "separate") << line;
    if (f[3] == "block") block_last_part = f[4];
    if (f[3] == "bouncer") bouncer_last_kind = f[2];
  }
  EXPECT_EQ(bodies, (std::set<std::string>{"block", "bouncer", "tossed", "coin", "pill"}));
  EXPECT_EQ(parts, (std::set<std::string>{"", "ground", "ramp"}));  // "": a separate event's
  EXPECT_EQ(block_last_part, "ground");
  EXPECT_EQ(bouncer_last_kind, "resting");

  const Result same = run_sim(
      dir, "'" + scene("contacts.pbtxt") + "' --csv '" + csv + "' --contacts-csv '" + csv + "'");
  EXPECT_EQ(same.status, 2);
  EXPECT_NE(same.err.find("--contacts-csv"), std::string::npos) << same.err;
}

}  // namespace
}  // namespace rigid::sim
