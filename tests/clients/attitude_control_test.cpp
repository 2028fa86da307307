// rigid-attitude's mathematics without a bus: the thrusters make the torque asked for with no net
// force and within their bound, and the law, run at 100 Hz on a state 10 ms old against the
// physics of config/scenes/attitude.pbtxt (the same World rigidd steps), settles within 1 degree
// from the scene's 90-degree offset and stays there.
#include "attitude_control.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <deque>
#include <numbers>

#include "physics/world.hpp"
#include "scene/scene.hpp"

namespace rigid::controllers {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

TEST(Thrusters, MakeTheTorqueAskedForWithNoNetForce) {
  const ThrusterSet set = ThrusterSet::box({0.5, 0.3, 0.2}, 5.0);
  for (const Vec3& tau :
       {Vec3(0.1, 0, 0), Vec3(0, -0.2, 0), Vec3(0, 0, 0.3), Vec3(0.3, -0.2, 0.1)}) {
    const Thrusts u = set.allocate(tau);
    EXPECT_LT((set.torque(u) - tau).norm(), 1e-12) << tau.transpose();
    EXPECT_LT(set.force(u).norm(), 1e-12);
  }
}

TEST(Thrusters, ADemandBeyondTheirBoundIsScaledDownKeepingItsDirection) {
  const ThrusterSet set = ThrusterSet::box({0.5, 0.3, 0.2}, 5.0);
  const Vec3 tau(40, -30, 20);  // far more than 5 N at these arms can give
  const Thrusts u = set.allocate(tau);
  double largest = 0;
  for (const double ui : u)
    largest = std::max(largest, std::abs(ui));
  EXPECT_NEAR(largest, 5.0, 1e-12);
  const Vec3 got = set.torque(u);
  EXPECT_LT((got.normalized() - tau.normalized()).norm(), 1e-12);
  EXPECT_NEAR(got.norm(), set.max_torque_along(tau.normalized()), 1e-9);
  EXPECT_LT(set.force(u).norm(), 1e-12);
}

TEST(Thrusters, SixThatCannotMakeEveryWrenchAreRefused) {
  const Thruster t{Vec3(0.1, 0, 0), Vec3::UnitY()};
  EXPECT_THROW(ThrusterSet({t, t, t, t, t, t}, 1.0), std::invalid_argument);
}

TEST(AttitudeLaw, SettlesWithinOneDegreeFromNinetyDegreesInTheAttitudeScene) {
  const scene::Scene s = scene::load_scene(std::string(RIGID_SCENES_DIR) + "/attitude.pbtxt");
  physics::World world(s.world);
  const physics::BodySpec& craft = s.world.bodies.at(0);
  const Quat target = Quat::Identity();
  ASSERT_NEAR(angle_between(world.state(0).q_WB, target) / kDeg, 90.0, 1e-9);
  // As rigid-attitude builds it: the box's half extents, 5 N thrusters.
  const AttitudeController law(craft.I_B, ThrusterSet::box({0.5, 0.3, 0.2}, 5.0), target);

  // rigidd ticks at 1 kHz and publishes every 10 ticks; the controller acts at 100 Hz on the
  // newest state it has, one publication old, and its thrusts hold until the next.
  const int ticks_per_control = 10;
  std::deque<physics::BodyState> published{world.state(0)};
  double settled_at = -1;
  double worst_after = 0;
  for (int control = 0; control < 1500; ++control) {  // 15 s
    const physics::BodyState seen = published.front();
    const Thrusts u = law.thrusts(seen.q_WB, seen.w_WB);
    for (const double ui : u)
      ASSERT_LE(std::abs(ui), 5.0 + 1e-12);
    world.clear_applied();
    const auto& thrusters = law.thrusters().thrusters();
    for (std::size_t i = 0; i < thrusters.size(); ++i)
      world.add_force(0, u[i] * thrusters[i].axis_B, thrusters[i].point_B, physics::Frame::kBody);
    world.step(ticks_per_control);
    published.push_back(world.state(0));
    if (published.size() > 2) published.pop_front();

    const double t = (control + 1) * 0.01;
    const double error = angle_between(world.state(0).q_WB, target) / kDeg;
    if (error < 1.0 && settled_at < 0) settled_at = t;
    if (settled_at >= 0) worst_after = std::max(worst_after, error);
    if (error >= 1.0) settled_at = -1;  // not settled until it stays
  }
  ASSERT_GT(settled_at, 0) << "never settled within 1 degree";
  EXPECT_LT(settled_at, 6.0) << "settled at " << settled_at << " s";
  EXPECT_LT(worst_after, 1.0);
  EXPECT_LT(angle_between(world.state(0).q_WB, target) / kDeg, 0.01);
  EXPECT_LT(world.state(0).w_WB.norm(), 1e-3);
  // No net force: the centre of mass stays where it was.
  EXPECT_LT(world.state(0).p_WBo.norm(), 1e-9);
}

}  // namespace
}  // namespace rigid::controllers
