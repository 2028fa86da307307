// Every built peer driver against physics, before any of its numbers is trusted: a projectile, a
// pure spin about a principal axis, the lever-arm torque of a force at a point (world and body
// frame), linear drag; and the racket flip at 1 ms against the peer survey's figures
// (bench/notes/peers.md). A
// wrong frame, sign, unit or step count in a driver fails here.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <string>

#include "peer_engine.hpp"
#include "peer_run.hpp"

namespace rigid::bench::peers {
namespace {

using physics::Mat3;

// One engine's mode, named as in the CSV.
struct EngineMode {
  const PeerEngine* engine;
  std::string mode;
  std::string name() const { return engine->name() + "_" + mode; }
};

class PeersTest : public ::testing::Test {
 protected:
  std::vector<std::unique_ptr<PeerEngine>> engines_ = built_engines();

  std::vector<EngineMode> engine_modes(const Case& c) const {
    std::vector<EngineMode> r;
    for (const auto& e : engines_) {
      for (const std::string& m : e->modes(c))
        r.push_back({e.get(), m});
    }
    return r;
  }
};

// MuJoCo's RK4 is the only peer method above first order.
bool is_rk4(const EngineMode& r) {
  return r.engine->name() == "mujoco" && r.mode.rfind("rk4", 0) == 0;
}

Case free_body(const Vec3& I, double mass) {
  Case c;
  c.name = "sanity";
  c.body.name = "b";
  c.body.mass = mass;
  c.body.I_B = I.asDiagonal();
  c.body.use_gravity = false;
  return c;
}

double angle_between(const Quat& a, const Quat& b) {
  const Quat d = a.conjugate() * b;
  return 2.0 * std::atan2(d.vec().norm(), std::abs(d.w()));
}

// Steps a world of 3 copies n times and checks the copies stayed identical (they are
// independent bodies: any difference means the driver couples them).
BodyState run(const EngineMode& r, const Case& c, double dt, long n) {
  const auto w = r.engine->make_world(c, r.mode, dt, 3);
  for (long i = 0; i < n; ++i)
    w->step();
  const BodyState s = w->state(0);
  for (int k = 1; k < 3; ++k) {
    const BodyState o = w->state(k);
    EXPECT_EQ(o.p_WBo, s.p_WBo);
    EXPECT_EQ(o.q_WB.coeffs(), s.q_WB.coeffs());
    EXPECT_EQ(o.v_WBo, s.v_WBo);
    EXPECT_EQ(o.w_WB, s.w_WB);
  }
  return s;
}

TEST_F(PeersTest, SomeEngineIsBuilt) {
  EXPECT_FALSE(engines_.empty());
  for (const auto& e : engines_)
    std::printf("%s: %s\n", e->name().c_str(), e->version().c_str());
}

// Constant gravity: every method integrates v exactly; semi-implicit Euler (every first-order
// peer method) is off in position by exactly g dt T / 2, RK4 by round-off only.
TEST_F(PeersTest, Projectile) {
  Case c = free_body({1, 2, 3}, 1.5);
  c.body.use_gravity = true;
  c.body.p_WBo = {0.5, -1, 2};
  c.body.v_WBo = {1, 2, 3};
  const double dt = 1e-3, T = 1.0;
  const Vec3 g = gravity_of(c);
  for (const EngineMode& r : engine_modes(c)) {
    SCOPED_TRACE(r.name());
    const BodyState s = run(r, c, dt, std::lround(T / dt));
    EXPECT_LT((s.v_WBo - (c.body.v_WBo + g * T)).norm(), 1e-9);
    const Vec3 exact = c.body.p_WBo + c.body.v_WBo * T + 0.5 * g * T * T;
    const double err = (s.p_WBo - exact).norm();
    if (is_rk4(r)) {
      EXPECT_LT(err, 1e-9);
    } else {
      EXPECT_NEAR(err, 0.5 * g.norm() * dt * T, 1e-9);
    }
    EXPECT_LT(angle_between(s.q_WB, c.body.q_WB), 1e-12);
  }
}

// A spin about a principal axis from a tilted start: w stays constant and the orientation turns
// about it at |w|. Catches the frame of the angular velocity (world against body) in each driver.
TEST_F(PeersTest, PureSpinAboutAPrincipalAxis) {
  Case c = free_body({1, 2, 3}, 1.0);
  c.body.q_WB = Quat(Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()));
  c.body.w_WB = c.body.q_WB * Vec3(0, 0, 3);
  const double dt = 1e-3, T = 1.0;
  const Quat exact = Quat(Eigen::AngleAxisd(3 * T, c.body.w_WB.normalized())) * c.body.q_WB;
  for (const EngineMode& r : engine_modes(c)) {
    SCOPED_TRACE(r.name());
    const BodyState s = run(r, c, dt, std::lround(T / dt));
    EXPECT_LT((s.w_WB - c.body.w_WB).norm(), 1e-9);
    // ODE's infinitesimal update loses ~(w dt)^3 / 12 per step: 2e-6 rad here.
    EXPECT_LT(angle_between(s.q_WB, exact), 1e-5);
  }
}

// One step from rest of a force at a body point: the angular acceleration is
// I_W^-1 ((R r) x f_W) and the linear one f_W / m, whatever the method.
void expect_lever_arm(const std::vector<EngineMode>& modes, const Case& c, const Vec3& f_W,
                      const Vec3& tau_W) {
  const double dt = 1e-4;
  const Mat3 R = c.body.q_WB.toRotationMatrix();
  const Vec3 alpha = R * c.body.I_B.inverse() * R.transpose() * tau_W;
  const Vec3 a = f_W / c.body.mass;
  for (const EngineMode& r : modes) {
    SCOPED_TRACE(r.name());
    const BodyState s = run(r, c, dt, 1);
    EXPECT_LT((s.w_WB / dt - alpha).norm(), 1e-6 * alpha.norm());
    EXPECT_LT((s.v_WBo / dt - a).norm(), 1e-6 * a.norm());
  }
}

TEST_F(PeersTest, WorldForceAtAPointGivesItsLeverArmTorque) {
  Case c = free_body({0.5, 1.0, 1.3}, 2.0);
  c.body.q_WB = Quat(Eigen::AngleAxisd(0.9, Vec3(1, -2, 0.5).normalized()));
  const Vec3 f{0.3, -1, 2}, r{0.4, 0.1, -0.2};
  c.loads.push_back(LoadSpec{.body = 0, .force = f, .p_BoQ_B = r});
  expect_lever_arm(engine_modes(c), c, f, (c.body.q_WB * r).cross(f));
}

TEST_F(PeersTest, BodyForceAtAPointTurnsWithTheBody) {
  Case c = free_body({0.5, 1.0, 1.3}, 2.0);
  c.body.q_WB = Quat(Eigen::AngleAxisd(0.9, Vec3(1, -2, 0.5).normalized()));
  const Vec3 f_B{0, 0, 4}, r{0.4, 0.1, 0};
  c.loads.push_back(LoadSpec{.body = 0, .force = f_B, .p_BoQ_B = r, .frame = Frame::kBody});
  const Vec3 f_W = c.body.q_WB * f_B;
  expect_lever_arm(engine_modes(c), c, f_W, (c.body.q_WB * r).cross(f_W));
}

// Linear drag -c v: the first step's deceleration is c v / m (to O(c dt / m) = 2e-4 for the
// implicit damping of MuJoCo).
TEST_F(PeersTest, LinearDragFirstStep) {
  Case c = free_body({0.4, 0.4, 0.4}, 1.0);
  c.body.linear_drag = 2.0;
  c.body.v_WBo = {10, 0, 5};
  const double dt = 1e-4;
  const Vec3 a = -c.body.linear_drag / c.body.mass * c.body.v_WBo;
  for (const EngineMode& r : engine_modes(c)) {
    SCOPED_TRACE(r.name());
    const BodyState s = run(r, c, dt, 1);
    EXPECT_LT(((s.v_WBo - c.body.v_WBo) / dt - a).norm(), 1e-3 * a.norm());
  }
}

// The stiff drag case at 1/60 s (c dt / m = 8.3): a user force is explicit in every engine and
// blows up; MuJoCo's own joint damping is implicit under Euler and implicit, and stays bounded.
TEST_F(PeersTest, StiffDragBlowsUpUnlessTheDampingIsImplicit) {
  for (const Case& c : hard_cases()) {
    if (c.name != "stiff_drag") continue;
    const Reference ref = compute_reference(c, true);
    for (const EngineMode& r : engine_modes(c)) {
      SCOPED_TRACE(r.name());
      const Row row = accuracy_run(*r.engine, c, r.mode, 1.0 / 60, ref);
      std::printf("stiff_drag at 1/60 s: %-31s worst position error %.3g m\n", r.name().c_str(),
                  row.err_x);
      const bool implicit_damping =
          r.name() == "mujoco_euler_damping" || r.name() == "mujoco_implicit_damping";
      if (implicit_damping) {
        EXPECT_LT(row.err_x, 1.0);
      } else {
        EXPECT_TRUE(std::isinf(row.err_x));
      }
    }
  }
}

// The racket flip at 1 ms, against the peer survey's figures (bench/notes/peers.md; within a
// factor of 3: same method, same ballpark), and how each mode's error falls from 2 ms to 1 ms.
TEST_F(PeersTest, RacketFlipMatchesPeersMd) {
  const std::map<std::string, double> peers_md = {{"mujoco_rk4", 7.2e-6},
                                                  {"mujoco_euler", 0.43},
                                                  {"mujoco_implicit", 0.42},
                                                  {"bullet_gyro_implicit", 0.42},
                                                  {"ode_gyro", 2.9}};
  const Case c = hard_cases().front();
  ASSERT_EQ(c.name, "racket_flip");
  const Reference ref = compute_reference(c, true);
  for (const EngineMode& r : engine_modes(c)) {
    SCOPED_TRACE(r.name());
    const double e1 = accuracy_run(*r.engine, c, r.mode, 1e-3, ref).err_q;
    const double e2 = accuracy_run(*r.engine, c, r.mode, 2e-3, ref).err_q;
    const auto it = peers_md.find(r.name());
    std::printf("racket_flip: %-31s error %.3g rad at 1 ms, %.3g at 2 ms (ratio %.3g)",
                r.name().c_str(), e1, e2, e2 / e1);
    if (it != peers_md.end()) std::printf(", PEERS.md: %.3g", it->second);
    std::printf("\n");
    if (it != peers_md.end()) {
      EXPECT_GT(e1, it->second / 3);
      EXPECT_LT(e1, it->second * 3);
    }
  }
}

// Ours behind the peers' interface (timed beside them by peer_work_precision) is the World that
// bench/work_precision steps, step for step and bit for bit, on every hard case.
TEST(RigidEngineTest, IsTheWorldItself) {
  const auto engine = make_rigid_engine();
  for (const Case& c : hard_cases()) {
    SCOPED_TRACE(c.name);
    const auto through = engine->make_world(c, "exact_rotor4", 1e-3, 2);
    physics::World direct(world_spec(c, "exact_rotor4", 1e-3, 2));
    for (int i = 0; i < 200; ++i) {
      through->step();
      direct.step();
    }
    for (int k = 0; k < 2; ++k) {
      const BodyState a = through->state(k), b = direct.state(k);
      EXPECT_EQ(a.p_WBo, b.p_WBo);
      EXPECT_EQ(a.q_WB.coeffs(), b.q_WB.coeffs());
      EXPECT_EQ(a.v_WBo, b.v_WBo);
      EXPECT_EQ(a.w_WB, b.w_WB);
    }
  }
  EXPECT_THROW(engine->make_world(hard_cases().front(), "no_such_integrator", 1e-3, 1),
               std::runtime_error);
}

}  // namespace
}  // namespace rigid::bench::peers
