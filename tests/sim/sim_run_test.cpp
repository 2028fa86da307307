// rigid-sim's run: CSV contents and row counts, the no-partial-file guarantee, the summary.
#include "sim/sim_run.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "common/world_csv.hpp"
#include "physics/integrator.hpp"
#include "scene/scene.hpp"
#include "test_dir.hpp"

namespace rigid::sim {
namespace {

namespace fs = std::filesystem;
using testing::read_file;
using testing::TestDir;

// 2 bodies; dt = 1 / (100 * 2) = 5 ms; a CSV row every 3 ticks = 6 steps by default.
constexpr std::string_view kScene = R"pb(
  world { rate_hz: 100 substeps: 2 publish_every: 3 }
  body {
    name: "ball"
    mass: 1
    shape { sphere { radius: 0.1 } }
    position { x: 0.1 }
  }
  body {
    name: "spinner"
    mass: 2
    inertia { x: 1 y: 2 z: 3 }
    angular_velocity { x: 0.1 y: 4 z: 0.1 }
    use_gravity: false
  }
)pb";

scene::Scene small_scene() {
  return scene::parse_scene(kScene, "small.pbtxt");
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    out.push_back(line);
  return out;
}

std::vector<std::string> fields(const std::string& line) {
  std::vector<std::string> out;
  std::istringstream in(line);
  for (std::string f; std::getline(in, f, ',');)
    out.push_back(f);
  return out;
}

SimOptions options(double duration, const std::string& csv) {
  SimOptions o;
  o.scene = "small.pbtxt";
  o.duration = duration;
  o.csv = csv;
  return o;
}

TEST(SimRun, CsvHeaderRowsAndFormat) {
  const TestDir dir;
  const std::string out = dir.file("out.csv");
  const RunSummary r = run(small_scene(), options(1.0, out));
  EXPECT_EQ(r.steps, 200);
  EXPECT_EQ(r.every, 3);
  EXPECT_FALSE(fs::exists(out + ".tmp"));
  const std::vector<std::string> rows = lines(read_file(out));
  ASSERT_FALSE(rows.empty());
  EXPECT_EQ(rows[0] + "\n", util::kStateCsvHeader);
  EXPECT_EQ(rows[0], "t,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz");
  // t = 0, every 6 steps (33 of them up to step 198), and the end (step 200): 35 times, 2 bodies.
  EXPECT_EQ(rows.size(), 1u + 2u * 35u);
  EXPECT_EQ(r.csv_rows, 70);
  for (std::size_t i = 1; i < rows.size(); ++i) {
    ASSERT_EQ(fields(rows[i]).size(), 15u) << rows[i];
  }
  // Rows at t = 0 for every body, in scene order; 17 significant digits.
  EXPECT_EQ(fields(rows[1])[0], "0");
  EXPECT_EQ(fields(rows[1])[1], "ball");
  EXPECT_EQ(fields(rows[1])[2], "0.10000000000000001");
  EXPECT_EQ(fields(rows[2])[1], "spinner");
  EXPECT_EQ(fields(rows[2])[13], "4");                    // wy
  EXPECT_EQ(fields(rows[3])[0], "0.029999999999999999");  // 6 steps of 5 ms
  EXPECT_EQ(std::stod(fields(rows.back())[0]), 1.0);
  EXPECT_EQ(fields(rows.back())[1], "spinner");
}

TEST(SimRun, EveryOverridesPublishEvery) {
  const TestDir dir;
  const std::string out = dir.file("out.csv");
  SimOptions o = options(1.0, out);
  o.every = 1;  // every tick = 2 steps: t = 0 and 100 ticks
  const RunSummary r = run(small_scene(), o);
  EXPECT_EQ(r.csv_rows, 2 * 101);
  EXPECT_EQ(lines(read_file(out)).size(), 1u + 2u * 101u);
}

TEST(SimRun, ZeroDurationWritesTheInitialState) {
  const TestDir dir;
  const std::string out = dir.file("out.csv");
  const RunSummary r = run(small_scene(), options(0.0, out));
  EXPECT_EQ(r.steps, 0);
  EXPECT_EQ(lines(read_file(out)).size(), 3u);
}

TEST(SimRun, DtAndIntegratorOverrides) {
  SimOptions o;
  o.duration = 0.1;
  o.dt = 1e-4;
  const physics::IntegratorInfo& last = physics::all_integrators().back();
  o.integrator = std::string(last.name);
  const RunSummary r = run(small_scene(), o);
  EXPECT_EQ(r.dt, 1e-4);
  EXPECT_EQ(r.steps, 1000);
  EXPECT_EQ(r.integrator, last.name);
  EXPECT_TRUE(r.csv.empty());
  EXPECT_EQ(r.csv_rows, 0);
}

TEST(SimRun, CsvThatCannotBeCreatedLeavesNothing) {
  const TestDir dir;
  const std::string out = dir.file("no/such/dir/out.csv");
  EXPECT_THROW(run(small_scene(), options(0.1, out)), std::runtime_error);
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(fs::exists(out + ".tmp"));
}

TEST(SimRun, TooManyStepsIsAUsageError) {
  SimOptions o;
  o.duration = 1e300;
  EXPECT_THROW(run(small_scene(), o), UsageError);
}

TEST(SimRun, SummaryTracksTheConservedQuantities) {
  SimOptions o;
  o.duration = 0.5;
  const RunSummary r = run(small_scene(), o);
  ASSERT_EQ(r.bodies.size(), 2u);
  // The ball falls freely: it gains kinetic energy, and has no angular momentum.
  EXPECT_EQ(r.bodies[0].name, "ball");
  EXPECT_EQ(r.bodies[0].motion, physics::BodyMotion::kSteadySpin);
  EXPECT_EQ(r.bodies[0].ke0, 0.0);
  EXPECT_NEAR(r.bodies[0].ke, 0.5 * 9.81 * 9.81 * 0.25, 1e-9);
  EXPECT_NEAR(r.bodies[0].p_final.z(), -0.5 * 9.81 * 0.25, 1e-9);
  // The spinner is torque-free: kinetic energy and angular momentum are conserved.
  EXPECT_EQ(r.bodies[1].motion, physics::BodyMotion::kTumbling);
  EXPECT_GT(r.bodies[1].ke0, 0.0);
  EXPECT_NEAR(r.bodies[1].ke, r.bodies[1].ke0, 1e-6 * r.bodies[1].ke0);
  EXPECT_LT((r.bodies[1].L - r.bodies[1].L0).norm(), 1e-6 * r.bodies[1].L0.norm());
  // Total energy (kinetic + potential) is conserved too.
  EXPECT_NEAR(r.energy, r.energy0, 1e-6 * std::abs(r.energy0) + 1e-9);
  EXPECT_GT(r.wall_seconds, 0.0);
  EXPECT_GE(r.wall_seconds, r.step_seconds);

  std::ostringstream text;
  print_summary(text, r);
  const std::string s = text.str();
  for (const char* fragment : {"small.pbtxt", "ball", "spinner", "steady_spin", "tumbling",
                               "total energy", "wall time", "ns per body-step"}) {
    EXPECT_NE(s.find(fragment), std::string::npos) << fragment << " not in:\n" << s;
  }
}

TEST(SimRun, ListIntegratorsMarksTheDefault) {
  std::ostringstream text;
  print_integrators(text);
  const std::string s = text.str();
  for (const physics::IntegratorInfo& i : physics::all_integrators()) {
    EXPECT_NE(s.find(i.name), std::string::npos) << i.name;
  }
  EXPECT_NE(s.find("* " + std::string(physics::default_integrator().name)), std::string::npos) << s;
}

}  // namespace
}  // namespace rigid::sim
