// Bodies touching each other in the World: isolated impacts at the closed-form instant with
// momentum (and, elastic, energy) kept; a row of touching balls passing a blow on; stacks that
// rest; collision filters; the same states for any thread count.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "physics/world.hpp"

namespace rigid::physics {
namespace {

constexpr double kG = 9.81;

BodySpec ball(const std::string& name, double r, double m, const Vec3& p, const Vec3& v,
              Surface s) {
  BodySpec b;
  b.name = name;
  b.mass = m;
  b.shape = Shape{ShapeKind::kSphere, Vec3(r, 0, 0)};
  b.I_B = shape_inertia(*b.shape, m);
  b.p_WBo = p;
  b.v_WBo = v;
  b.surface = s;
  return b;
}

BodySpec box(const std::string& name, const Vec3& size, double m, const Vec3& p, Surface s) {
  BodySpec b;
  b.name = name;
  b.mass = m;
  b.shape = Shape{ShapeKind::kBox, size};
  b.I_B = shape_inertia(*b.shape, m);
  b.p_WBo = p;
  b.surface = s;
  return b;
}

Vec3 momentum(const World& w) {
  Vec3 p = Vec3::Zero();
  for (int i = 0; i < w.body_count(); ++i)
    p += w.body_spec(i).mass * w.state(i).v_WBo;
  return p;
}

TEST(WorldPairs, TwoSpheresHeadOnMeetAtTheClosedFormTimeAndSwapVelocities) {
  WorldSpec spec;
  spec.dt = 1e-3;
  spec.g_W = Vec3::Zero();
  const Surface elastic{1.0, 0.0};
  spec.bodies.push_back(ball("a", 0.1, 1.0, Vec3(0, 0, 0), Vec3(3, 0, 0), elastic));
  spec.bodies.push_back(ball("b", 0.1, 1.0, Vec3(1, 0, 0), Vec3(-1, 0, 0), elastic));
  World w(spec);
  std::vector<ContactEvent> events;
  for (int i = 0; i < 500; ++i) {
    w.step();
    for (const ContactEvent& e : w.contact_events())
      events.push_back(e);
  }
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].other, 1);
  EXPECT_EQ(events[0].part, -1);
  EXPECT_NEAR(events[0].time, 0.8 / 4.0, 1e-12);
  EXPECT_NEAR(w.state(0).v_WBo.x(), -1.0, 1e-12);
  EXPECT_NEAR(w.state(1).v_WBo.x(), 3.0, 1e-12);
  EXPECT_NEAR((momentum(w) - Vec3(2, 0, 0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(w.total_energy(), 0.5 * 9 + 0.5 * 1, 1e-12);
}

TEST(WorldPairs, AnObliqueElasticImpactSendsEqualSpheresOffAtRightAngles) {
  WorldSpec spec;
  spec.dt = 1e-3;
  spec.g_W = Vec3::Zero();
  const Surface elastic{1.0, 0.0};
  spec.bodies.push_back(ball("cue", 0.1, 1.0, Vec3(0, 0, 0), Vec3(2, 0, 0), elastic));
  spec.bodies.push_back(ball("target", 0.1, 1.0, Vec3(1, 0.1, 0), Vec3::Zero(), elastic));
  World w(spec);
  w.step(1000);
  const Vec3 va = w.state(0).v_WBo, vb = w.state(1).v_WBo;
  EXPECT_NEAR(va.dot(vb), 0.0, 1e-12);
  EXPECT_NEAR((va + vb - Vec3(2, 0, 0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(va.squaredNorm() + vb.squaredNorm(), 4.0, 1e-12);
  // The target leaves along the line of centres at impact: 30 degrees here (offset = r).
  EXPECT_NEAR(std::atan2(-vb.y(), vb.x()), -std::asin(0.1 / 0.2), 1e-10);
}

TEST(WorldPairs, NewtonsCradleSendsOneBallOutAndLeavesTheOthersStill) {
  WorldSpec spec;
  spec.dt = 1e-3;
  spec.g_W = Vec3::Zero();
  const Surface elastic{1.0, 0.0};
  spec.bodies.push_back(ball("b0", 0.1, 1.0, Vec3(-0.5, 0, 0), Vec3(1, 0, 0), elastic));
  for (int k = 1; k < 5; ++k)
    spec.bodies.push_back(
        ball("b" + std::to_string(k), 0.1, 1.0, Vec3(0.2 * (k - 1), 0, 0), Vec3::Zero(), elastic));
  World w(spec);
  w.step(1000);
  for (int k = 0; k < 4; ++k)
    EXPECT_NEAR(w.state(k).v_WBo.norm(), 0.0, 1e-12) << k;
  EXPECT_NEAR(w.state(4).v_WBo.x(), 1.0, 1e-12);
  EXPECT_NEAR((momentum(w) - Vec3(1, 0, 0)).norm(), 0.0, 1e-12);
}

TEST(WorldPairs, ABoxDroppedFlatOnABoxComesToRestOnItWithoutTurning) {
  WorldSpec spec;
  spec.dt = 1e-3;
  spec.g_W = Vec3(0, 0, -kG);
  PlaneSpec ground;
  ground.name = "ground";
  spec.planes.push_back(ground);
  const Surface s{0.2, 0.6};
  spec.bodies.push_back(box("bottom", Vec3(0.4, 0.4, 0.2), 2.0, Vec3(0, 0, 0.1), s));
  spec.bodies.push_back(box("top", Vec3(0.2, 0.2, 0.2), 1.0, Vec3(0.05, 0, 0.5), s));
  World w(spec);
  w.step(3000);
  EXPECT_NEAR(w.state(0).p_WBo.z(), 0.1, 1e-5);
  EXPECT_NEAR(w.state(1).p_WBo.z(), 0.3, 1e-5);
  EXPECT_NEAR(w.state(1).p_WBo.x(), 0.05, 1e-5);
  EXPECT_LT(w.state(1).q_WB.angularDistance(Quat::Identity()), 1e-6);
  EXPECT_LT(w.state(1).v_WBo.norm(), 1e-3);
}

TEST(WorldPairs, ATowerOfTenBoxesStandsForSixtySeconds) {
  for (const double dt : {1e-3, 1.0 / 60}) {
    WorldSpec spec;
    spec.dt = dt;
    spec.g_W = Vec3(0, 0, -kG);
    PlaneSpec ground;
    ground.name = "ground";
    spec.planes.push_back(ground);
    const Surface s{0.0, 0.6};
    for (int k = 0; k < 10; ++k)
      spec.bodies.push_back(
          box("b" + std::to_string(k), Vec3(0.2, 0.2, 0.2), 1.0, Vec3(0, 0, 0.1 + 0.2 * k), s));
    World w(spec);
    std::vector<Vec3> start;
    for (int k = 0; k < 10; ++k)
      start.push_back(w.state(k).p_WBo);
    w.step(static_cast<std::int64_t>(std::llround(60.0 / dt)));
    for (int k = 0; k < 10; ++k)
      EXPECT_LT((w.state(k).p_WBo - start[k]).norm(), 1e-3) << "dt " << dt << " box " << k;
  }
}

TEST(WorldPairs, CollisionFiltersLetBodiesPassThroughEachOther) {
  WorldSpec spec;
  spec.dt = 1e-3;
  spec.g_W = Vec3::Zero();
  const Surface elastic{1.0, 0.0};
  BodySpec a = ball("a", 0.1, 1.0, Vec3(0, 0, 0), Vec3(1, 0, 0), elastic);
  BodySpec b = ball("b", 0.1, 1.0, Vec3(1, 0, 0), Vec3(-1, 0, 0), elastic);
  a.collision_group = 2;
  b.collision_mask = ~std::uint32_t{2};
  spec.bodies = {a, b};
  World w(spec);
  w.step(1000);
  EXPECT_NEAR(w.state(0).v_WBo.x(), 1.0, 1e-15);
  EXPECT_NEAR(w.state(1).v_WBo.x(), -1.0, 1e-15);
}

TEST(WorldPairs, StatesAreBitIdenticalForAnyThreadCount) {
  WorldSpec spec;
  spec.dt = 1e-3;
  spec.g_W = Vec3(0, 0, -kG);
  PlaneSpec ground;
  ground.name = "ground";
  spec.planes.push_back(ground);
  const Surface s{0.3, 0.5};
  for (int i = 0; i < 300; ++i) {
    spec.bodies.push_back(
        ball("b" + std::to_string(i), 0.05, 1.0,
             Vec3(0.09 * (i % 10), 0.09 * ((i / 10) % 10), 0.1 + 0.12 * (i / 100)),
             Vec3(0.01 * (i % 3), 0, 0), s));
  }
  World one(spec), three(spec);
  three.set_threads(3);
  for (int k = 0; k < 300; ++k) {
    one.step();
    three.step();
  }
  for (int i = 0; i < one.body_count(); ++i) {
    ASSERT_EQ(one.state(i).p_WBo, three.state(i).p_WBo) << i;
    ASSERT_EQ(one.state(i).q_WB.coeffs(), three.state(i).q_WB.coeffs()) << i;
  }
}

// A tumbling body grazing another (a point on a falling sphere's surface, moving apart) takes no
// impulse: its spin, energy and angular momentum are what a free rotor keeps, though the contact
// stage reads and writes its state while the pair is close.
TEST(WorldPairs, ATumblingBodyThatGrazesAnotherKeepsItsSpin) {
  WorldSpec spec;
  spec.dt = 5e-3;
  BodySpec ball_spec = ball("ball", 0.1, 1.0, Vec3(0.1, 0, 0), Vec3::Zero(), Surface{0.0, 0.5});
  spec.bodies.push_back(ball_spec);
  BodySpec spinner;
  spinner.name = "spinner";
  spinner.mass = 2.0;
  spinner.I_B = Vec3(1, 2, 3).asDiagonal();
  spinner.w_WB = Vec3(0.1, 4, 0.1);
  spinner.use_gravity = false;
  spec.bodies.push_back(spinner);
  World w(spec);
  const Vec3 L0 = spinner.I_B * spinner.w_WB;
  const double ke0 = 0.5 * spinner.w_WB.dot(L0);
  for (int i = 0; i < 100; ++i) {
    w.step();
    const BodyState s = w.state(1);
    const Mat3 R = s.q_WB.toRotationMatrix();
    const Vec3 L = R * spinner.I_B * R.transpose() * s.w_WB;
    ASSERT_NEAR((L - L0).norm(), 0.0, 1e-9 * L0.norm()) << "step " << i;
    ASSERT_NEAR(0.5 * s.w_WB.dot(L), ke0, 1e-9 * ke0) << "step " << i;
    ASSERT_EQ(s.p_WBo, Vec3::Zero());
  }
}

}  // namespace
}  // namespace rigid::physics
