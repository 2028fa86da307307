// What the work-precision drivers share and the report relies on: the world a case builds, the
// steps of the sweeps, and the reference cache that lets two drivers of one report run compute
// each reference once.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>

#include "hard_cases.hpp"

namespace rigid::bench {
namespace {

TEST(BenchHardCasesTest, WorldSpecCopiesTheBodyAndItsLoads) {
  for (const Case& c : hard_cases()) {
    const physics::WorldSpec ws = world_spec(c, "rk4", 1e-3, 3);
    ASSERT_EQ(ws.bodies.size(), 3u);
    ASSERT_EQ(ws.loads.size(), 3 * c.loads.size());
    for (std::size_t k = 0; k < ws.loads.size(); ++k)
      EXPECT_EQ(ws.loads[k].body, static_cast<int>(k / std::max<std::size_t>(1, c.loads.size())));
    EXPECT_EQ(ws.integrator, "rk4");
    EXPECT_EQ(ws.g_W, gravity_of(c));
  }
}

// Ours are swept from 1/10 s, and at every step the peers are.
TEST(BenchHardCasesTest, OurSweepContainsThePeersSweep) {
  for (bool quick : {false, true}) {
    const std::vector<double> ours = our_sweep_steps(quick), peers = sweep_steps(quick);
    EXPECT_EQ(ours.front(), 0.1);
    for (double dt : peers)
      EXPECT_NE(std::find(ours.begin(), ours.end(), dt), ours.end()) << dt;
    EXPECT_TRUE(std::is_sorted(ours.rbegin(), ours.rend()));
  }
}

// A cached reference reads back bit for bit, under its own case only.
TEST(BenchHardCasesTest, ReferenceCacheRoundTrips) {
  const std::string cache =
      (std::filesystem::temp_directory_path() / ("hard_cases_test_" + std::to_string(::getpid())))
          .string();
  std::filesystem::remove(cache);
  Case c = hard_cases()[5];
  ASSERT_EQ(c.name, "thruster");
  c.duration = 0.05;  // a short run keeps the reference cheap
  c.reference_steps = 2000;
  const Reference computed = compute_reference(c, false, cache);
  const Reference cached = compute_reference(c, false, cache);
  EXPECT_EQ(cached.name, computed.name);
  EXPECT_EQ(cached.state.x, computed.state.x);
  EXPECT_EQ(cached.state.v, computed.state.v);
  EXPECT_EQ(cached.state.q.coeffs(), computed.state.q.coeffs());
  EXPECT_EQ(cached.state.w, computed.state.w);
  Case other = c;
  other.description += " (changed)";
  other.reference_steps = 1000;
  EXPECT_NE(compute_reference(other, false, cache).name, computed.name);
  std::filesystem::remove(cache);
}

}  // namespace
}  // namespace rigid::bench
