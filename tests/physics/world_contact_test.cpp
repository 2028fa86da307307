// The World with static geometry, against the closed forms of the classic cases at dt = 1 ms,
// 1/240 s and 1/60 s (gravity 9.81, the plane z = 0): bodies land, bounce, slide, roll and rest,
// every impact at the time the closed form gives, never inside a part; and a world whose bodies
// never reach a part steps bit for bit as one without parts.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "physics/world.hpp"

namespace rigid::physics {
namespace {

constexpr double kG = 9.81;

WorldSpec ground_world(double dt, double e, double mu) {
  WorldSpec w;
  w.dt = dt;
  w.g_W = Vec3(0, 0, -kG);
  PlaneSpec ground;
  ground.name = "ground";
  ground.n_W = Vec3::UnitZ();
  ground.surface = Surface{e, mu};
  w.planes.push_back(ground);
  return w;
}

BodySpec sphere(double r, double m, const Vec3& p, Surface s = Surface{0.0, 0.5}) {
  BodySpec b;
  b.name = "ball";
  b.mass = m;
  b.shape = Shape{ShapeKind::kSphere, Vec3(r, 0, 0)};
  b.I_B = shape_inertia(*b.shape, m);
  b.p_WBo = p;
  b.surface = s;
  return b;
}

BodySpec cube(double a, double m, const Vec3& p, Surface s = Surface{0.0, 0.5}) {
  BodySpec b;
  b.name = "cube";
  b.mass = m;
  b.shape = Shape{ShapeKind::kBox, Vec3(a, a, a)};
  b.I_B = shape_inertia(*b.shape, m);
  b.p_WBo = p;
  b.surface = s;
  return b;
}

// Steps until t_end, collecting every event.
std::vector<ContactEvent> run(World& w, double t_end) {
  std::vector<ContactEvent> events;
  const auto n = static_cast<std::int64_t>(std::llround(t_end / w.dt()));
  for (std::int64_t i = 0; i < n; ++i) {
    w.step();
    for (const ContactEvent& e : w.contact_events())
      events.push_back(e);
  }
  return events;
}

class WorldContact : public ::testing::TestWithParam<double> {};
INSTANTIATE_TEST_SUITE_P(Dt, WorldContact, ::testing::Values(1e-3, 1.0 / 240, 1.0 / 60));

TEST_P(WorldContact, AnElasticSphereBouncesForTenSecondsAtTheClosedFormTimes) {
  const double dt = GetParam(), r = 0.1, h0 = 1.0;
  WorldSpec spec = ground_world(dt, 1.0, 0.5);
  spec.bodies.push_back(sphere(r, 1.0, Vec3(0, 0, h0), Surface{1.0, 0.5}));
  World w(spec);
  const double t1 = std::sqrt(2 * (h0 - r) / kG), period = 2 * t1;
  double lowest = INFINITY, apex = 0.0;
  int k = 0;
  const auto n = static_cast<std::int64_t>(std::llround(10.0 / dt));
  for (std::int64_t i = 0; i < n; ++i) {
    w.step();
    for (const ContactEvent& e : w.contact_events()) {
      ASSERT_EQ(e.kind, ContactEventKind::kImpact);
      EXPECT_NEAR(e.time, t1 + k * period, 1e-9) << k;  // 1 ns: the target is 1 us
      ++k;
    }
    lowest = std::min(lowest, w.state(0).p_WBo.z());
    // After the 12th bounce, the apex its state rises to (z + v_z^2 / 2g, exact in free flight).
    if (k == 12) {
      const BodyState s = w.state(0);
      apex = s.p_WBo.z() + s.v_WBo.z() * s.v_WBo.z() / (2 * kG);
    }
  }
  EXPECT_NEAR(apex, h0, 1e-9);
  EXPECT_EQ(k, static_cast<int>((10.0 - t1) / period) + 1);
  EXPECT_GE(lowest, r - 1e-12);  // never inside the plane
  EXPECT_NEAR(w.total_energy(), kG * h0, 1e-9);
}

TEST_P(WorldContact, AHalfElasticSphereComesToRestAtTheSeriesEnd) {
  const double dt = GetParam(), r = 0.1, h0 = 1.0, e = 0.5;
  WorldSpec spec = ground_world(dt, e, 0.5);
  spec.bodies.push_back(sphere(r, 1.0, Vec3(0, 0, h0), Surface{e, 0.5}));
  World w(spec);
  const std::vector<ContactEvent> events = run(w, 3.0);
  const double t1 = std::sqrt(2 * (h0 - r) / kG);
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events.back().kind, ContactEventKind::kResting);
  EXPECT_NEAR(events.back().time, t1 * (1 + e) / (1 - e), 1e-9);
  EXPECT_EQ(w.support(0), World::Support::kResting);
  EXPECT_NEAR(w.state(0).p_WBo.z(), r, 1e-15);
  EXPECT_EQ(w.state(0).v_WBo, Vec3::Zero());
}

TEST_P(WorldContact, ACubeDroppedOneMicronLandsFlatAndThenNothingMovesForTenSeconds) {
  const double dt = GetParam(), a = 0.2;
  WorldSpec spec = ground_world(dt, 0.5, 0.5);
  spec.bodies.push_back(cube(a, 1.0, Vec3(0.3, -0.1, 0.5 * a + 1e-6)));
  World w(spec);
  run(w, 0.1);
  ASSERT_EQ(w.support(0), World::Support::kResting);
  const BodyState settled = w.state(0);
  EXPECT_NEAR(settled.p_WBo.z(), 0.5 * a, 1e-15);
  run(w, 10.0);
  EXPECT_EQ(w.state(0).p_WBo, settled.p_WBo);
  EXPECT_EQ(w.state(0).q_WB.coeffs(), settled.q_WB.coeffs());
}

TEST_P(WorldContact, ASlidingCubeStopsWhereTheClosedFormSays) {
  const double dt = GetParam(), a = 0.2, mu = 0.5, v0 = 2.0;
  WorldSpec spec = ground_world(dt, 0.0, mu);
  BodySpec b = cube(a, 1.0, Vec3(0, 0, 0.5 * a), Surface{0.0, mu});
  b.v_WBo = Vec3(v0, 0, 0);
  spec.bodies.push_back(b);
  World w(spec);
  const std::vector<ContactEvent> events = run(w, 1.0);
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events.back().kind, ContactEventKind::kResting);
  EXPECT_NEAR(events.back().time, v0 / (mu * kG), 1e-9);
  EXPECT_NEAR(w.state(0).p_WBo.x(), v0 * v0 / (2 * mu * kG), 1e-9);
  EXPECT_NEAR(w.state(0).p_WBo.z(), 0.5 * a, 1e-12);
}

TEST_P(WorldContact, ATumblingCubeNeverGainsEnergyAndComesToRestOnAFace) {
  const double dt = GetParam(), a = 0.2;
  WorldSpec spec = ground_world(dt, 0.5, 0.5);
  BodySpec b = cube(a, 1.0, Vec3(0, 0, 1.0), Surface{0.5, 0.5});
  b.q_WB = Quat(Eigen::AngleAxisd(0.5, Vec3(1, 2, 0.3).normalized()));
  b.w_WB = Vec3(3.0, -2.0, 5.0);
  spec.bodies.push_back(b);
  World w(spec);
  double e = w.total_energy();
  const auto n = static_cast<std::int64_t>(std::llround(10.0 / dt));
  for (std::int64_t i = 0; i < n && w.support(0) != World::Support::kResting; ++i) {
    w.step();
    const double e1 = w.total_energy();
    ASSERT_LE(e1, e + 1e-12 * std::abs(e)) << i;
    e = e1;
  }
  ASSERT_EQ(w.support(0), World::Support::kResting);
  EXPECT_EQ(w.contact_capped_steps(), 0);
  EXPECT_NEAR(w.state(0).p_WBo.z(), 0.5 * a, 1e-9);
  const Mat3 R = w.state(0).q_WB.toRotationMatrix();
  EXPECT_NEAR(R.row(2).cwiseAbs().maxCoeff(), 1.0, 1e-9);
}

TEST(WorldContactCost, BodiesThatNeverReachAPartStepBitForBitAsWithoutParts) {
  // Spinning bodies far above a plane they never reach in the run, with and without the plane.
  WorldSpec plain;
  plain.dt = 1e-3;
  plain.g_W = Vec3(0, 0, -kG);
  for (int i = 0; i < 20; ++i) {
    BodySpec b = cube(0.2, 1.0 + i, Vec3(i, 0, 1000.0));
    b.name = "b" + std::to_string(i);
    b.I_B = Vec3(1.0, 2.0 + 0.1 * i, 3.0).asDiagonal();
    b.w_WB = Vec3(0.3, 4.0, 0.1 * i);
    b.v_WBo = Vec3(0, 0, 1.0);
    plain.bodies.push_back(b);
  }
  WorldSpec with = plain;
  PlaneSpec ground;
  ground.name = "ground";
  with.planes.push_back(ground);
  World a(plain), b(with);
  a.step(2000);
  b.step(2000);
  for (int i = 0; i < a.body_count(); ++i) {
    EXPECT_EQ(a.state(i).p_WBo, b.state(i).p_WBo);
    EXPECT_EQ(a.state(i).q_WB.coeffs(), b.state(i).q_WB.coeffs());
    EXPECT_EQ(a.state(i).w_WB, b.state(i).w_WB);
  }
  EXPECT_TRUE(b.contact_events().empty());
}

}  // namespace
}  // namespace rigid::physics
