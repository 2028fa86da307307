// World: validation, the model each body compiles to, state in and out, frozen axes, kinematic
// bodies, impulses, reset, determinism, and no allocation while stepping.
#include "physics/world.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <new>
#include <random>

#include "allocation_counter.hpp"
#include "physics/spec_store.hpp"
#include "test_util.hpp"

namespace rigid::test {
namespace {

using physics::BodyMotion;
using physics::BodyState;
using physics::Frame;
using physics::LoadSpec;
using physics::Mat3;
using physics::SpecError;

Mat3 rotated(const Vec3& I, const Quat& q) {
  const Mat3 R = q.toRotationMatrix();
  return R * I.asDiagonal() * R.transpose();
}

// Expects the spec to be rejected with a SpecError about `field` of body `body`.
void expect_rejected(const WorldSpec& ws, int body, const std::string& field) {
  try {
    World w(ws);
    ADD_FAILURE() << "accepted; expected an error on " << field;
  } catch (const SpecError& e) {
    EXPECT_EQ(e.body(), body) << e.what();
    EXPECT_EQ(e.field(), field) << e.what();
    EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
  }
}

TEST(WorldSpec, RejectsWhatCannotBeSimulated) {
  const WorldSpec good = one_body(body("a", {1, 2, 3}), 1e-3, "");
  {
    WorldSpec ws = good;
    ws.bodies[0].mass = -1;
    expect_rejected(ws, 0, "mass");
  }
  {
    WorldSpec ws = good;
    ws.bodies[0].I_B = Vec3(1, 1, 3).asDiagonal();  // 1 + 1 < 3: no rigid body has these moments
    expect_rejected(ws, 0, "inertia");
  }
  {
    WorldSpec ws = good;
    ws.bodies[0].I_B = Vec3(1, -1, 1).asDiagonal();
    expect_rejected(ws, 0, "inertia");
  }
  {
    WorldSpec ws = good;
    ws.bodies[0].q_WB = Quat(0, 0, 0, 0);
    expect_rejected(ws, 0, "orientation");
  }
  {
    WorldSpec ws = good;
    ws.bodies[0].w_WB.x() = std::nan("");
    expect_rejected(ws, 0, "angular_velocity");
  }
  {
    WorldSpec ws = good;
    ws.bodies[0].linear_drag = -0.1;
    expect_rejected(ws, 0, "linear_drag");
  }
  {
    WorldSpec ws = good;
    ws.bodies[0].freeze_rotation = {true, false, false};
    expect_rejected(ws, 0, "freeze_rotation");
  }
  {
    WorldSpec ws = good;
    ws.bodies.push_back(ws.bodies[0]);
    expect_rejected(ws, 1, "name");
  }
  {
    WorldSpec ws = good;
    ws.integrator = "verlet";
    expect_rejected(ws, -1, "integrator");
  }
  {
    WorldSpec ws = good;
    ws.dt = 0;
    expect_rejected(ws, -1, "dt");
  }
  {
    WorldSpec ws = good;
    ws.loads.push_back(LoadSpec{.body = 3});
    try {
      World w(ws);
      ADD_FAILURE();
    } catch (const SpecError& e) {
      EXPECT_EQ(e.load(), 0);
    }
  }
}

TEST(WorldSpec, NormalisesANonUnitOrientation) {
  WorldSpec ws = one_body(body("a", {1, 2, 3}), 1e-3, "");
  ws.bodies[0].q_WB = Quat(2, 0, 0, 0);
  World w(ws);
  EXPECT_NEAR(w.state(0).q_WB.norm(), 1.0, 1e-15);
}

TEST(WorldModel, EachBodyCompilesToTheCheapestExactModel) {
  WorldSpec ws;
  ws.bodies.push_back(body("sphere", {2, 2, 2}));
  ws.bodies.push_back(body("oblate", {1, 1, 1.5}));
  ws.bodies.push_back(body("prolate", {1, 2, 2}));
  ws.bodies.push_back(body("general", {1, 2, 2.5}));
  BodySpec p = body("particle", {1, 1, 1});
  p.has_inertia = false;
  ws.bodies.push_back(p);
  BodySpec locked = body("locked", {1, 2, 2.5});
  locked.freeze_rotation = {true, true, true};
  ws.bodies.push_back(locked);
  BodySpec hinge = body("hinge", {1, 2, 2.5});
  hinge.freeze_rotation = {true, true, false};
  ws.bodies.push_back(hinge);
  BodySpec kin = body("kinematic", {1, 2, 2.5}, {0, 0, 1});
  kin.kinematic = true;
  ws.bodies.push_back(kin);
  World w(ws);
  EXPECT_EQ(w.body_motion(0), BodyMotion::kSteadySpin);
  EXPECT_EQ(w.body_motion(1), BodyMotion::kPrecession);
  EXPECT_EQ(w.body_motion(2), BodyMotion::kPrecession);
  EXPECT_EQ(w.body_motion(3), BodyMotion::kTumbling);
  EXPECT_EQ(w.body_motion(4), BodyMotion::kTranslation);
  EXPECT_EQ(w.body_motion(5), BodyMotion::kTranslation);
  EXPECT_EQ(w.body_motion(6), BodyMotion::kSteadySpin);
  EXPECT_EQ(w.body_motion(7), BodyMotion::kSteadySpin);
  EXPECT_EQ(w.find_body("prolate"), 2);
  EXPECT_EQ(w.find_body("nope"), -1);
}

// A body's kinematic flag and frozen axes are its motion type and allowed degrees of freedom,
// whatever group it compiled to; body_spec gives them back as the spec had them.
TEST(WorldModel, MotionTypeAndAllowedDofsAreTheSpecsFlags) {
  using physics::AllowedDofs;
  using physics::MotionType;
  WorldSpec ws;
  ws.bodies.push_back(body("free", {1, 2, 2.5}));
  BodySpec hinge = body("hinge", {1, 2, 2.5});
  hinge.freeze_rotation = {true, false, true};
  hinge.freeze_translation = {false, false, true};
  ws.bodies.push_back(hinge);
  BodySpec still = body("still", {1, 2, 2.5});
  still.kinematic = true;
  ws.bodies.push_back(still);
  BodySpec spinning = body("spinning", {1, 2, 2.5}, {0, 0, 1});
  spinning.kinematic = true;
  spinning.freeze_translation = {true, false, false};
  ws.bodies.push_back(spinning);
  World w(ws);
  EXPECT_EQ(w.motion_type(0), MotionType::kDynamic);
  EXPECT_EQ(w.allowed_dofs(0), AllowedDofs::kAll);
  EXPECT_EQ(w.motion_type(1), MotionType::kDynamic);
  EXPECT_EQ(w.allowed_dofs(1),
            AllowedDofs::kTranslationX | AllowedDofs::kTranslationY | AllowedDofs::kRotationY);
  EXPECT_EQ(physics::locked_rotations(w.allowed_dofs(1)), 2);
  EXPECT_EQ(w.body_motion(1), BodyMotion::kSteadySpin);
  EXPECT_EQ(w.motion_type(2), MotionType::kKinematic);
  EXPECT_EQ(w.body_motion(2), BodyMotion::kTranslation);
  EXPECT_EQ(w.motion_type(3), MotionType::kKinematic);
  EXPECT_EQ(w.allowed_dofs(3),
            AllowedDofs::kTranslationY | AllowedDofs::kTranslationZ | AllowedDofs::kAllRotation);
  EXPECT_EQ(w.body_motion(3), BodyMotion::kSteadySpin);
  for (int id = 0; id < w.body_count(); ++id) {
    const BodySpec b = w.body_spec(id);
    EXPECT_EQ(b.kinematic, ws.bodies[id].kinematic) << id;
    EXPECT_EQ(b.freeze_translation, ws.bodies[id].freeze_translation) << id;
    EXPECT_EQ(b.freeze_rotation, ws.bodies[id].freeze_rotation) << id;
  }
  EXPECT_EQ(physics::to_string(BodyMotion::kPrecession), "precession");
  EXPECT_EQ(physics::to_string(MotionType::kKinematic), "kinematic");
}

// One body of each model (isotropic, axisymmetric both ways, general), each with its inertia
// given in a frame B tilted from its principal frame by `tilt`.
WorldSpec tilted_bodies(const Quat& tilt) {
  WorldSpec ws;
  int k = 0;
  for (const Vec3& I : {Vec3(2, 2, 2), Vec3(1, 1, 1.5), Vec3(1, 2, 2), Vec3(1, 2, 2.5)}) {
    BodySpec b = body("b" + std::to_string(k++), I);
    b.I_B = rotated(I, tilt);
    ws.bodies.push_back(b);
  }
  return ws;
}

// A full tensor is diagonalised at load and its principal frame kept: the state reported in B
// is the state given in B, for every model.
TEST(WorldModel, StateRoundTripsThroughThePrincipalFrame) {
  const Quat tilt(Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()));
  WorldSpec ws = tilted_bodies(tilt);
  World w(ws);
  const BodyState in{{1, -2, 3},
                     Quat(Eigen::AngleAxisd(1.1, Vec3(0, 1, 1).normalized())),
                     {0.5, 0.25, -1},
                     {0.3, -0.2, 0.9}};
  for (int i = 0; i < w.body_count(); ++i) {
    w.set_state(i, in);
    const BodyState out = w.state(i);
    EXPECT_LT((out.p_WBo - in.p_WBo).norm(), 1e-15);
    EXPECT_LT(angle_between(out.q_WB, in.q_WB), 1e-15);
    EXPECT_LT((out.v_WBo - in.v_WBo).norm(), 1e-15);
    EXPECT_LT((out.w_WB - in.w_WB).norm(), 1e-15);
    // L = R_WB I_B R_WB^T w in W, whatever frame the model integrates in.
    const Mat3 R = in.q_WB.toRotationMatrix();
    EXPECT_LT((w.angular_momentum_W(i) - R * w.body_spec(i).I_B * R.transpose() * in.w_WB).norm(),
              1e-14);
  }
}

// physics::rotate is Eigen's q * v to the last bit (the published w_WB did not change when
// write_states stopped calling Eigen's out-of-line rotation), over unit quaternions and vectors
// spread over many magnitudes and signs.
TEST(WorldModel, RotateIsEigensQuaternionTimesVectorBitForBit) {
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> u(-1.0, 1.0), e(-8.0, 8.0);
  const auto bits = [](double x) { return std::bit_cast<std::uint64_t>(x); };
  for (int i = 0; i < 20000; ++i) {
    const Quat q = Quat(u(rng), u(rng), u(rng), u(rng)).normalized();
    const Vec3 v = Vec3(u(rng), u(rng), u(rng))
                       .cwiseProduct(Vec3(std::pow(10.0, e(rng)), std::pow(10.0, e(rng)),
                                          std::pow(10.0, e(rng))));
    const Vec3 a = physics::rotate(q, v), b = q * v;
    for (int j = 0; j < 3; ++j)
      ASSERT_EQ(bits(a[j]), bits(b[j])) << "q " << q.coeffs().transpose() << " v " << v.transpose();
  }
}

// write_states is state(id) for every body, bit for bit, in body-id order: bodies of every model
// (tilted, point masses, frozen axes) with distinct states, some pushed so that their model's
// entries regroup out of id order.
TEST(WorldModel, WriteStatesIsStateOfEveryBodyBitForBit) {
  const Quat tilt(Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()));
  WorldSpec ws = tilted_bodies(tilt);
  for (const WorldSpec& more : {tilted_bodies(tilt.conjugate()), tilted_bodies(Quat::Identity())})
    ws.bodies.insert(ws.bodies.end(), more.bodies.begin(), more.bodies.end());
  BodySpec particle = body("particle", {1, 1, 1});
  particle.has_inertia = false;
  ws.bodies.insert(ws.bodies.begin() + 3, particle);
  BodySpec hinge = body("hinge", {1, 2, 2.5});
  hinge.freeze_rotation = {true, true, false};
  ws.bodies.insert(ws.bodies.begin() + 7, hinge);
  for (std::size_t i = 0; i < ws.bodies.size(); ++i)
    ws.bodies[i].name = "b" + std::to_string(i);
  World w(ws);
  const int n = w.body_count();
  for (int i = 0; i < n; ++i) {
    const double a = 0.1 * (i + 1);
    w.set_state(i, BodyState{{a, -2 * a, 3 * a},
                             Quat(Eigen::AngleAxisd(a, Vec3(1, -a, 2).normalized())),
                             {a, 0.5, -a},
                             {0.3 + a, -0.2, 0.9 * a}});
  }
  for (int i = n - 1; i >= 0; i -= 3)
    w.add_torque(i, {0.1, -0.2, 0.3}, Frame::kBody);
  for (int s = 0; s < 5; ++s)
    w.step();
  std::vector<double> p(3 * n), q(4 * n), v(3 * n), o(3 * n);
  w.write_states({p.data(), q.data(), v.data(), o.data()});
  const auto bits = [](double x) { return std::bit_cast<std::uint64_t>(x); };
  for (int i = 0; i < n; ++i) {
    const BodyState s = w.state(i);
    const auto k = static_cast<std::size_t>(i);
    for (int j = 0; j < 3; ++j) {
      EXPECT_EQ(bits(p[3 * k + j]), bits(s.p_WBo[j])) << "body " << i;
      EXPECT_EQ(bits(v[3 * k + j]), bits(s.v_WBo[j])) << "body " << i;
      EXPECT_EQ(bits(o[3 * k + j]), bits(s.w_WB[j])) << "body " << i;
    }
    EXPECT_EQ(bits(q[4 * k]), bits(s.q_WB.w())) << "body " << i;
    EXPECT_EQ(bits(q[4 * k + 1]), bits(s.q_WB.x())) << "body " << i;
    EXPECT_EQ(bits(q[4 * k + 2]), bits(s.q_WB.y())) << "body " << i;
    EXPECT_EQ(bits(q[4 * k + 3]), bits(s.q_WB.z())) << "body " << i;
  }
}

TEST(WorldModel, KinematicBodiesMoveWithTheirVelocitiesAndIgnoreForces) {
  BodySpec b = body("k", {1, 2, 3}, {0, 0, 2});
  b.kinematic = true;
  b.use_gravity = true;
  b.v_WBo = {1, 0, 0};
  WorldSpec ws = one_body(b, 0.01, "");
  ws.g_W = {0, 0, -9.81};
  ws.loads.push_back(LoadSpec{.body = 0, .force = {5, 5, 5}, .p_BoQ_B = {1, 0, 0}});
  World w(ws);
  w.step(100);
  const BodyState s = w.state(0);
  EXPECT_NEAR(s.p_WBo.x(), 1.0, 1e-14);
  EXPECT_NEAR(s.p_WBo.z(), 0.0, 1e-14);
  EXPECT_LT(angle_between(s.q_WB, Quat(Eigen::AngleAxisd(2.0, Vec3::UnitZ()))), 1e-14);
}

TEST(WorldModel, FrozenTranslationAxesHoldStill) {
  BodySpec b = body("f", {1, 2, 3});
  b.use_gravity = true;
  b.freeze_translation = {false, false, true};
  b.v_WBo = {1, 2, 3};
  WorldSpec ws = one_body(b, 0.01, "");
  ws.g_W = {0, 0, -9.81};
  World w(ws);
  w.step(100);
  EXPECT_EQ(w.state(0).p_WBo.z(), 0.0);
  EXPECT_EQ(w.state(0).v_WBo.z(), 0.0);
  EXPECT_NEAR(w.state(0).p_WBo.y(), 2.0, 1e-13);
}

// Two frozen rotation axes leave a hinge about the third world axis: w stays on it and grows at
// (tau . e) / I_e whatever the other torque components.
TEST(WorldModel, AHingeTurnsOnlyAboutItsFreeAxis) {
  const Quat tilt(Eigen::AngleAxisd(0.4, Vec3(1, 1, 0).normalized()));
  BodySpec b = body("h", {1, 2, 3});
  b.I_B = rotated({1, 2, 3}, tilt);
  b.q_WB = tilt.conjugate();  // so that the body's principal axes are the world's at t = 0
  b.freeze_rotation = {true, true, false};
  WorldSpec ws = one_body(b, 1e-3, "");
  World w(ws);
  w.add_torque(0, {5, -7, 3}, Frame::kWorld);
  w.step(1000);
  const BodyState s = w.state(0);
  EXPECT_NEAR(s.w_WB.x(), 0.0, 1e-13);
  EXPECT_NEAR(s.w_WB.y(), 0.0, 1e-13);
  EXPECT_NEAR(s.w_WB.z(), 3.0 / 3.0 * 1.0, 1e-12);  // I_zz = 3 in W, for 1 s
}

TEST(WorldModel, AnImpulseChangesMomentaAtTheNextStep) {
  WorldSpec ws = one_body(body("a", {1, 2, 3}), 1e-9, "rk4");
  ws.bodies[0].mass = 2.0;
  World w(ws);
  w.apply_impulse(0, {0, 4, 0}, {1, 0, 0}, Frame::kWorld);
  EXPECT_EQ(w.state(0).v_WBo, Vec3::Zero());
  w.step();
  const BodyState s = w.state(0);
  EXPECT_NEAR(s.v_WBo.y(), 2.0, 1e-12);
  EXPECT_NEAR(s.w_WB.z(), 4.0 / 3.0, 1e-8);  // (r x J)_z / I_zz
}

TEST(WorldModel, ResetRestoresTheInitialState) {
  WorldSpec ws = one_body(body("a", {1, 2, 3}, {1, 2, 3}), 1e-3, "");
  World w(ws);
  const BodyState s0 = w.state(0);
  w.add_force(0, {1, 0, 0}, {0, 1, 0}, Frame::kBody);
  w.step(100);
  EXPECT_GT(angle_between(w.state(0).q_WB, s0.q_WB), 0.1);
  EXPECT_NEAR(w.time(), 0.1, 1e-15);
  w.reset();
  EXPECT_EQ(w.time(), 0.0);
  EXPECT_LT(angle_between(w.state(0).q_WB, s0.q_WB), 1e-15);
  EXPECT_LT((w.state(0).w_WB - s0.w_WB).norm(), 1e-15);
  w.step(100);  // and the applied force is gone: torque-free motion again
  World fresh(ws);
  fresh.step(100);
  EXPECT_LT(angle_between(w.state(0).q_WB, fresh.state(0).q_WB), 1e-14);
}

// A body whose scheme diverges (RK4 with linear drag at c dt / m = 5: x13.7 per step) is caught by
// the guard, put back to its last good state and frozen at rest; the rest of the world goes on as
// if it were alone, and reset() thaws it.
TEST(WorldGuard, FreezesADivergingBodyAndTheRestGoesOn) {
  BodySpec bad = body("bad", {1, 1, 1});
  bad.linear_drag = 5.0 / 1e-2;  // c dt / m = 5
  bad.v_WBo = {1, 0, 0};
  BodySpec good = body("good", {1, 2, 3}, {0.3, 1, 2});
  WorldSpec ws;
  ws.dt = 1e-2;
  ws.g_W.setZero();
  ws.integrator = "rk4";
  ws.bodies = {bad, good};
  World w(ws), alone(one_body(good, 1e-2, "rk4"));
  w.step(1000);
  alone.step(1000);
  ASSERT_EQ(w.frozen_bodies().size(), 1u);
  EXPECT_EQ(w.frozen_bodies()[0], 0);
  EXPECT_TRUE(w.is_frozen(0));
  EXPECT_FALSE(w.is_frozen(1));
  const BodyState s = w.state(0);
  EXPECT_TRUE(s.p_WBo.allFinite());
  EXPECT_EQ(s.v_WBo, Vec3::Zero());
  EXPECT_LE(s.p_WBo.norm(), 1e100);
  // frozen: loads and impulses no longer move it
  w.add_force(0, {1, 1, 1}, Vec3::Zero(), Frame::kWorld);
  w.apply_impulse(0, {1, 1, 1}, Vec3::Zero(), Frame::kWorld);
  w.step(10);
  EXPECT_EQ(w.state(0).p_WBo, s.p_WBo);
  EXPECT_EQ(w.state(1).q_WB.coeffs(), [&] {
    alone.step(10);
    return alone.state(0).q_WB.coeffs();
  }());
  w.reset();
  EXPECT_TRUE(w.frozen_bodies().empty());
  EXPECT_FALSE(w.is_frozen(0));
  w.step(1);
  EXPECT_NE(w.state(0).p_WBo.x(), 0.0);  // moving again (RK4 here: R(-5) = -2.5 per step)
}

// The guard checks a slice of the bodies after each step (no step pays for all of them): each
// body once in every kGuardEvery steps, after the steps at its phase; the slices are even, and a
// lone body is checked at multiples of kGuardEvery. A body made absurd right after a check is
// left alone for kGuardEvery - 1 steps, then frozen at the pose that check passed, and no other
// body is frozen.
TEST(WorldGuard, ChecksEachBodyOnceInEveryKGuardEveryStepsAtItsPhase) {
  constexpr int kEvery = World::kGuardEvery;
  for (int n : {1, 3, 64, 200}) {
    SCOPED_TRACE("bodies " + std::to_string(n));
    WorldSpec ws;
    ws.dt = 1e-3;
    ws.g_W.setZero();
    for (int i = 0; i < n; ++i)
      ws.bodies.push_back(body("b" + std::to_string(i), {1, 2, 3}, {0.01 * i, 1, -0.5}));
    const World fresh(ws);
    std::vector<int> per_phase(kEvery, 0);
    for (int id = 0; id < n; ++id) {
      const int k = fresh.guard_phase(id);
      ASSERT_GE(k, 0);
      ASSERT_LT(k, kEvery);
      ++per_phase[k];
    }
    for (int k = 0; k < kEvery; ++k) {
      EXPECT_LE(per_phase[k], (n + kEvery - 1) / kEvery) << "phase " << k;
      EXPECT_GE(per_phase[k], n / kEvery) << "phase " << k;
    }
    EXPECT_EQ(fresh.guard_phase(n - 1), 0);
    for (int id : {0, n / 2, n - 1}) {
      SCOPED_TRACE("body " + std::to_string(id));
      World w(ws);
      const int k = w.guard_phase(id);
      w.step(kEvery + k);  // its check after this step passes
      const BodyState good = w.state(id);
      BodyState bad = good;
      bad.v_WBo = Vec3(1e300, 0, 0);
      w.set_state(id, bad);
      w.step(kEvery - 1);
      EXPECT_FALSE(w.is_frozen(id)) << "checked before its turn";
      w.step();
      ASSERT_TRUE(w.is_frozen(id)) << "not checked at its turn";
      ASSERT_EQ(w.frozen_bodies().size(), 1u);
      const BodyState s = w.state(id);
      EXPECT_EQ(s.p_WBo, good.p_WBo);
      EXPECT_EQ(s.q_WB.coeffs(), good.q_WB.coeffs());
      EXPECT_EQ(s.v_WBo, Vec3::Zero());
      EXPECT_EQ(s.w_WB, Vec3::Zero());
    }
  }
}

TEST(WorldGuard, RejectsANonFiniteState) {
  World w(one_body(body("a", {1, 2, 3}), 1e-3, ""));
  BodyState s = w.state(0);
  s.v_WBo.x() = std::nan("");
  EXPECT_THROW(w.set_state(0, s), std::invalid_argument);
}

WorldSpec busy_world(const std::string& integrator) {
  WorldSpec ws;
  ws.dt = 1e-3;
  ws.integrator = integrator;
  int k = 0;
  for (const Vec3& I : {Vec3(2, 2, 2), Vec3(1, 1, 1.5), Vec3(1, 2, 2.5), Vec3(1, 2, 2.5)}) {
    BodySpec b = body("b" + std::to_string(k), I, {0.3 * k, 2, -1});
    b.use_gravity = true;
    b.linear_drag = 0.1 * k;
    b.angular_drag = 0.05 * k;
    ws.bodies.push_back(b);
    ws.loads.push_back(LoadSpec{.body = k,
                                .force = {0, 1, 0},
                                .p_BoQ_B = {0.2, 0, 0},
                                .frame = k % 2 ? Frame::kBody : Frame::kWorld});
    ++k;
  }
  BodySpec p = body("p", {1, 1, 1}, Vec3::Zero());
  p.has_inertia = false;
  ws.bodies.push_back(p);
  return ws;
}

TEST(WorldStep, IsBitIdenticalForIdenticalInputs) {
  for (const auto& info : physics::all_integrators()) {
    const WorldSpec ws = busy_world(std::string(info.name));
    World a(ws), b(ws);
    a.step(500);
    World c = a;  // a copy continues identically too
    a.step(500);
    b.step(1000);
    c.step(500);
    for (int i = 0; i < a.body_count(); ++i) {
      EXPECT_EQ(a.state(i).q_WB.coeffs(), b.state(i).q_WB.coeffs()) << info.name;
      EXPECT_EQ(a.state(i).p_WBo, b.state(i).p_WBo) << info.name;
      EXPECT_EQ(a.state(i).w_WB, c.state(i).w_WB) << info.name;
    }
  }
}

// General bodies share the exact rotor's constants by their moments (model.hpp: GenGroup::rotors):
// bodies that differ in drag alone share one, bodies with other moments have their own. Each body
// of a mixed world steps to the same bits as in a world of its own, whatever it shares.
TEST(WorldStep, GeneralBodiesStepAsAloneWhateverTheyShare) {
  std::vector<BodySpec> bodies;
  const Vec3 w0(0.4, 3.0, -0.2);
  for (const auto& [I, drag] : {std::pair{Vec3(1, 2, 3), 0.0},
                                {Vec3(1, 2, 3), 0.05},
                                {Vec3(0.5, 1.0, 1.3), 0.0},
                                {Vec3(1, 2, 3), 0.05},
                                {Vec3(0.5, 1.0, 1.3), 0.2}}) {
    BodySpec b = body("b" + std::to_string(bodies.size()), I, w0 + 0.1 * bodies.size() * w0);
    b.angular_drag = drag;
    bodies.push_back(b);
  }
  WorldSpec all = one_body(bodies[0], 1e-3, "");
  all.bodies = bodies;
  World w(all);
  w.step(300);
  for (std::size_t k = 0; k < bodies.size(); ++k) {
    World alone(one_body(bodies[k], 1e-3, ""));
    alone.step(300);
    const int id = static_cast<int>(k);
    EXPECT_EQ(w.body_motion(id), BodyMotion::kTumbling);
    EXPECT_EQ(w.state(id).q_WB.coeffs(), alone.state(0).q_WB.coeffs()) << "body " << k;
    EXPECT_EQ(w.state(id).w_WB, alone.state(0).w_WB) << "body " << k;
  }
}

TEST(WorldStep, AllocatesNothing) {
  for (const auto& info : physics::all_integrators()) {
    World w(busy_world(std::string(info.name)));
    w.step(2);
    const long before = allocation_count();
    w.clear_applied();
    w.add_force(1, {1, 2, 3}, {0, 0, 1}, Frame::kBody);
    w.apply_impulse(2, {0, 0, 1}, {1, 0, 0}, Frame::kWorld);
    w.step(100);
    EXPECT_EQ(allocation_count(), before) << info.name;
  }
}

}  // namespace
}  // namespace rigid::test

// What the World keeps cold and small (world.cpp): names looked up in a sorted index, the spec's
// loads only for the bodies that have any, impulses in a list of the bodies that got one, the
// principal moments and q_BP derived from the model. Each gives what the dense copies gave.
namespace rigid::test {
namespace {

TEST(WorldCold, EveryNameIsFoundAndTheFirstRepeatIsTheDuplicate) {
  WorldSpec ws;
  const int n = 1000;
  for (int i = 0; i < n; ++i) {
    // Names out of id order, some prefixes of others.
    ws.bodies.push_back(body("b" + std::to_string((i * 7919) % n), {1, 2, 3}));
  }
  World w(ws);
  for (int i = 0; i < n; ++i)
    EXPECT_EQ(w.find_body(ws.bodies[i].name), i);
  EXPECT_EQ(w.find_body("b"), -1);
  EXPECT_EQ(w.find_body("b1000"), -1);
  EXPECT_EQ(w.find_body(""), -1);

  // Two repeated names: the error names the body that repeats a name first in scene order.
  ws.bodies[700].name = ws.bodies[20].name;
  ws.bodies[300].name = ws.bodies[299].name;
  expect_rejected(ws, 300, "name");
  // A body before the repeat with a bad field is reported first, as before.
  ws.bodies[100].mass = -1;
  expect_rejected(ws, 100, "mass");
}

// World keeps the specs compactly (spec_store.hpp: bodies with equal parameters share them):
// body_spec gives back each body's spec bit for bit, whichever fields it shares with others.
TEST(WorldCold, BodySpecGivesBackEveryBodyAsGiven) {
  const auto bits = [](double x) { return std::bit_cast<std::uint64_t>(x); };
  WorldSpec ws;
  for (int i = 0; i < 60; ++i) {
    BodySpec b =
        body(std::string(static_cast<std::size_t>(1 + i % 23), 'a' + i % 26) + std::to_string(i),
             {1, 2, 3});
    // Every fourth body has its own parameters; the rest share one of two kinds.
    b.mass = i % 4 == 0 ? 1.0 + i : 2.0 + i % 2;
    b.I_B = rotated(Vec3(2, 2.5, 3 + 0.25 * (i % 4)),
                    Quat(Eigen::AngleAxisd(0.1 * (i % 4), Vec3::UnitY())));
    b.linear_drag = i % 3 == 0 ? 0.0 : -0.0;  // equal, but not the same bits
    b.angular_drag = 0.01 * (i % 2);
    b.use_gravity = i % 5 != 0;
    b.kinematic = i % 7 == 0;
    b.has_inertia = i % 11 != 0;
    b.freeze_translation = {i % 13 == 0, false, i % 17 == 0};
    b.freeze_rotation = i % 19 == 0 ? std::array<bool, 3>{true, true, false}
                                    : std::array<bool, 3>{false, false, false};
    b.p_WBo = Vec3(i, -2.0 * i, 1e-300 * i);
    // Every fourth body starts its own way; the rest share one of six starts (the world keeps
    // each distinct start once), two of which differ only in the sign of a zero.
    const int k = i % 4 == 0 ? i : i % 3;
    b.q_WB = Quat(Eigen::AngleAxisd(0.05 * k, Vec3(1, -1, 2).normalized()));
    b.v_WBo = Vec3(0.5 * k, i % 2 == 0 ? 0.0 : -0.0, -1);
    b.w_WB = Vec3(0, 0.25 * k, 3);
    ws.bodies.push_back(b);
  }
  const World w(ws);
  for (int i = 0; i < w.body_count(); ++i) {
    const BodySpec& in = ws.bodies[i];
    const BodySpec out = w.body_spec(i);
    SCOPED_TRACE(in.name);
    EXPECT_EQ(out.name, in.name);
    EXPECT_EQ(w.body_name(i), in.name);
    EXPECT_EQ(bits(out.mass), bits(in.mass));
    for (int k = 0; k < 9; ++k)
      EXPECT_EQ(bits(out.I_B.data()[k]), bits(in.I_B.data()[k]));
    EXPECT_EQ(bits(out.linear_drag), bits(in.linear_drag));
    EXPECT_EQ(bits(out.angular_drag), bits(in.angular_drag));
    EXPECT_EQ(out.use_gravity, in.use_gravity);
    EXPECT_EQ(out.kinematic, in.kinematic);
    EXPECT_EQ(out.has_inertia, in.has_inertia);
    EXPECT_EQ(out.freeze_translation, in.freeze_translation);
    EXPECT_EQ(out.freeze_rotation, in.freeze_rotation);
    for (int a = 0; a < 3; ++a) {
      EXPECT_EQ(bits(out.p_WBo[a]), bits(in.p_WBo[a]));
      EXPECT_EQ(bits(out.v_WBo[a]), bits(in.v_WBo[a]));
      EXPECT_EQ(bits(out.w_WB[a]), bits(in.w_WB[a]));
    }
    // The orientation normalised, as the world steps it.
    const Quat q = in.q_WB.normalized();
    for (int k = 0; k < 4; ++k)
      EXPECT_EQ(bits(out.q_WB.coeffs()[k]), bits(q.coeffs()[k]));
  }
  // Equal starts are kept once: k = 0, 1, 2 with +0 or -0 (six), and the fourteen of i = 4, 8,
  // ..., 56 (i = 0 starts as the bodies with k = 0 and +0 do).
  EXPECT_EQ(physics::detail::SpecStore(ws.bodies).distinct_starts(), 20);
  // reset() puts every body back where a new world starts it, to the bit.
  World stepped(ws);
  stepped.step(10);
  stepped.reset();
  for (int i = 0; i < w.body_count(); ++i) {
    const BodyState a = stepped.state(i), b = w.state(i);
    SCOPED_TRACE(ws.bodies[i].name);
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(bits(a.p_WBo[k]), bits(b.p_WBo[k]));
      EXPECT_EQ(bits(a.v_WBo[k]), bits(b.v_WBo[k]));
      EXPECT_EQ(bits(a.w_WB[k]), bits(b.w_WB[k]));
    }
    for (int k = 0; k < 4; ++k)
      EXPECT_EQ(bits(a.q_WB.coeffs()[k]), bits(b.q_WB.coeffs()[k]));
  }
}

TEST(WorldCold, MomentsAndPrincipalFramesComeFromTheModel) {
  const Quat tilt(Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()));
  WorldSpec ws = tilted_bodies(tilt);
  BodySpec kin = body("kinematic", {1, 2, 2.5}, {0, 0, 1});
  kin.kinematic = true;
  ws.bodies.push_back(kin);
  BodySpec point = body("point", {1, 1, 1});
  point.has_inertia = false;
  ws.bodies.push_back(point);
  const World w(ws);
  const Vec3 expected[] = {{2, 2, 2}, {1, 1, 1.5}, {2, 2, 1}, {1, 2, 2.5}, {1, 2, 2.5}, {0, 0, 0}};
  for (int i = 0; i < w.body_count(); ++i) {
    EXPECT_LT((w.principal_moments(i) - expected[i]).norm(), 1e-12) << i;
    // q_BP diagonalises the spec's tensor (P = B for point masses and isotropic bodies).
    const Mat3 R = w.q_BP(i).toRotationMatrix();
    const Mat3 I_P = R.transpose() * ws.bodies[i].I_B * R;
    if (w.body_motion(i) == BodyMotion::kPrecession || w.body_motion(i) == BodyMotion::kTumbling) {
      EXPECT_LT((I_P - Mat3(w.principal_moments(i).asDiagonal())).norm(), 1e-12) << i;
    } else {
      EXPECT_EQ(w.q_BP(i).coeffs(), Quat::Identity().coeffs()) << i;
    }
  }
}

// Applied loads cleared (all at once or body by body) give back exactly the spec's loads: a world
// pushed and cleared moves bit for bit as one never pushed.
TEST(WorldCold, ClearingAppliedLoadsRestoresTheScenesOwnLoads) {
  WorldSpec ws;
  for (int i = 0; i < 40; ++i) {
    BodySpec b =
        body("b" + std::to_string(i), i % 2 ? Vec3(1, 2, 3) : Vec3(1, 1, 1.4), {0.1 * i, 1, -0.5});
    if (i % 9 == 4) b.angular_drag = 0.2;
    ws.bodies.push_back(b);
    if (i % 5 == 3) {
      ws.loads.push_back(
          LoadSpec{.body = i, .force = {0, 0, 2}, .p_BoQ_B = {0.3, 0, 0.1}, .frame = Frame::kBody});
    }
  }
  World plain(ws), pushed(ws);
  for (int k = 0; k < 30; ++k) {
    for (int i = 0; i < pushed.body_count(); ++i) {
      pushed.add_force(i, {1, -1, 0.5}, {0, 0.2, 0}, Frame::kWorld);
      pushed.add_torque(i, {0, 0.3, 0}, Frame::kBody);
    }
    if (k % 2 == 0) {
      pushed.clear_applied();
    } else {
      for (int i = pushed.body_count() - 1; i >= 0; --i)
        pushed.clear_applied(i);
    }
    plain.step();
    pushed.step();
  }
  for (int i = 0; i < plain.body_count(); ++i) {
    EXPECT_EQ(plain.state(i).q_WB.coeffs(), pushed.state(i).q_WB.coeffs()) << i;
    EXPECT_EQ(plain.state(i).w_WB, pushed.state(i).w_WB) << i;
    EXPECT_EQ(plain.state(i).v_WBo, pushed.state(i).v_WBo) << i;
  }
  // And they are there: a body with a scene load moves differently from one without.
  WorldSpec unloaded = ws;
  unloaded.loads.clear();
  World bare(unloaded);
  bare.step(30);
  EXPECT_NE(plain.state(3).v_WBo, bare.state(3).v_WBo);
  EXPECT_EQ(plain.state(2).v_WBo, bare.state(2).v_WBo);
}

// The scene's loads are kept once per distinct value (world.cpp: base_loads): each body still
// gets back its own when applied loads are cleared. Bodies with the same load, another load, drag
// alone, a load and drag, and nothing step in one world, pushed and cleared every step, to the
// same bits as each alone and never pushed.
TEST(WorldCold, EachBodyGetsItsOwnSceneLoadsBack) {
  WorldSpec ws;
  ws.dt = 1e-3;
  ws.g_W.setZero();
  const Vec3 fA(0, 0, 2), fB(0.5, -1, 0);
  struct Kind {
    const Vec3* force;
    double drag;
  };
  const Kind kinds[] = {{&fA, 0.0}, {&fB, 0.0},     {&fA, 0.0}, {nullptr, 0.3},
                        {&fA, 0.3}, {nullptr, 0.0}, {&fB, 0.0}};
  for (const Kind& k : kinds) {
    const int i = static_cast<int>(ws.bodies.size());
    BodySpec b = body("b" + std::to_string(i), Vec3(1, 2, 3), {0.2 * i, 1, -0.5});
    b.angular_drag = k.drag;
    ws.bodies.push_back(b);
    if (k.force != nullptr) {
      ws.loads.push_back(
          LoadSpec{.body = i, .force = *k.force, .p_BoQ_B = {0.3, 0, 0.1}, .frame = Frame::kBody});
    }
  }
  World w(ws);
  for (int step = 0; step < 40; ++step) {
    for (int i = 0; i < w.body_count(); ++i)
      w.add_force(i, {1, -1, 0.5}, {0, 0.2, 0}, Frame::kWorld);
    if (step % 2 == 0) {
      w.clear_applied();
    } else {
      for (int i = 0; i < w.body_count(); ++i)
        w.clear_applied(i);
    }
    w.step();
  }
  for (int i = 0; i < w.body_count(); ++i) {
    WorldSpec one = ws;
    one.bodies = {ws.bodies[static_cast<std::size_t>(i)]};
    one.loads.clear();
    for (LoadSpec l : ws.loads) {
      if (l.body != i) continue;
      l.body = 0;
      one.loads.push_back(l);
    }
    World alone(one);
    alone.step(40);
    EXPECT_EQ(w.state(i).q_WB.coeffs(), alone.state(0).q_WB.coeffs()) << "body " << i;
    EXPECT_EQ(w.state(i).w_WB, alone.state(0).w_WB) << "body " << i;
    EXPECT_EQ(w.state(i).v_WBo, alone.state(0).v_WBo) << "body " << i;
  }
}

// Bodies whose scene loads are alike share those loads' terms (model.hpp: Group::terms): pushing
// one, frozen or not, leaves the others' loads alone. Five thrusters alike and one other: body 0
// is pushed at every step, body 5 every other one (and cleared in between), body 2 is frozen by
// the guard at its second check; the rest step bit for bit as in a world where nothing is pushed.
TEST(WorldCold, PushingABodyLeavesTheSceneLoadsItSharesAlone) {
  for (const char* integrator : {"", "rk4"}) {
    SCOPED_TRACE(std::string("integrator '") + integrator + "'");
    WorldSpec ws;
    ws.dt = 1e-3;
    ws.g_W.setZero();
    ws.integrator = integrator;
    for (int i = 0; i < 6; ++i) {
      BodySpec b = body("b" + std::to_string(i), Vec3(1, 2, 3), {0.2 * i, 1, -0.5});
      ws.bodies.push_back(b);
      ws.loads.push_back(LoadSpec{.body = i,
                                  .force = i == 4 ? Vec3(1, 0, 0) : Vec3(0, 0, 2),
                                  .p_BoQ_B = {0.3, 0, 0.1},
                                  .frame = Frame::kBody});
    }
    World plain(ws), pushed(ws);
    for (int step = 0; step < 130; ++step) {
      pushed.clear_applied(0);
      pushed.add_force(0, {1, -1, 0.5}, {0, 0.2, 0}, Frame::kWorld);
      pushed.add_torque(0, {0, 0.3, 0}, Frame::kBody);
      if (step % 2 == 0) {
        pushed.add_force(5, {0, 0, 1e3}, {0.1, 0, 0}, Frame::kBody);
      } else {
        pushed.clear_applied(5);
      }
      // Body 2 diverges (a state the guard refuses) just before its second check.
      if (step + 1 == World::kGuardEvery + pushed.guard_phase(2)) {
        BodyState s = pushed.state(2);
        s.v_WBo = Vec3(1e300, 0, 0);
        pushed.set_state(2, s);
      }
      plain.step();
      pushed.step();
    }
    ASSERT_EQ(pushed.frozen_bodies().size(), 1u);
    EXPECT_EQ(pushed.frozen_bodies()[0], 2);
    for (int i : {1, 3, 4}) {
      EXPECT_EQ(plain.state(i).q_WB.coeffs(), pushed.state(i).q_WB.coeffs()) << "body " << i;
      EXPECT_EQ(plain.state(i).w_WB, pushed.state(i).w_WB) << "body " << i;
      EXPECT_EQ(plain.state(i).v_WBo, pushed.state(i).v_WBo) << "body " << i;
    }
    for (int i : {0, 5})
      EXPECT_NE(plain.state(i).w_WB, pushed.state(i).w_WB) << "body " << i;
    // Cleared and reset, the pushed ones step as the others again.
    pushed.reset();
    plain.reset();
    pushed.step(20);
    plain.step(20);
    for (int i = 0; i < 6; ++i)
      EXPECT_EQ(plain.state(i).w_WB, pushed.state(i).w_WB) << "body " << i;
  }
}

TEST(WorldCold, ImpulsesOnABodySumAndResetDropsThePendingOnes) {
  WorldSpec ws;
  for (int i = 0; i < 3; ++i)
    ws.bodies.push_back(body("b" + std::to_string(i), {1, 2, 3}));
  ws.g_W.setZero();
  World w(ws);
  w.apply_impulse(1, {1, 0, 0}, {0, 0, 0}, Frame::kWorld);
  w.apply_impulse(2, {0, 1, 0}, {0, 0, 0}, Frame::kWorld);
  w.apply_impulse(1, {0.5, 0, 0}, {0, 0, 0}, Frame::kWorld);
  w.step();
  EXPECT_EQ(w.state(1).v_WBo, Vec3(1.5, 0, 0));  // mass 1
  EXPECT_EQ(w.state(2).v_WBo, Vec3(0, 1, 0));
  EXPECT_EQ(w.state(0).v_WBo, Vec3::Zero());
  w.step();  // applied once only
  EXPECT_EQ(w.state(1).v_WBo, Vec3(1.5, 0, 0));
  w.apply_impulse(0, {3, 0, 0}, {0, 0, 0}, Frame::kWorld);
  w.reset();
  w.step();
  EXPECT_EQ(w.state(0).v_WBo, Vec3::Zero());
  // After the reset a new impulse on the same body is taken again.
  w.apply_impulse(0, {2, 0, 0}, {0, 0, 0}, Frame::kWorld);
  w.step();
  EXPECT_EQ(w.state(0).v_WBo, Vec3(2, 0, 0));
}

}  // namespace
}  // namespace rigid::test
