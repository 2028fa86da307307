// Closed-form solutions, and the discrete results the integrators themselves predict (Jolt style).
#include <gtest/gtest.h>

#include <numbers>

#include "test_util.hpp"

namespace rigid::test {
namespace {

using physics::BodyState;
using physics::Frame;
using physics::LoadSpec;

WorldSpec projectile(const std::string& integrator, double dt) {
  BodySpec b = body("ball", {0.4, 0.4, 0.4});
  b.use_gravity = true;
  b.v_WBo = {3, 0, 12};
  WorldSpec ws = one_body(b, dt, integrator);
  ws.g_W = {0, 0, -9.81};
  return ws;
}

// Every scheme whose translation is exact for a constant acceleration (the splittings' kicks are
// exact, the exponential translation is exact) lands on the parabola to round-off.
TEST(Analytic, ProjectileIsExactForTheSplittingsAndRk4) {
  for (const std::string name :
       {"exact_rotor4", "exact_rotor", "rk4", "dlm", "notes_leapfrog", "notes_midpoint"}) {
    World w(projectile(name, 1.0 / 60));
    w.step(120);
    const double t = w.time();
    EXPECT_NEAR(w.state(0).p_WBo.x(), 3 * t, 1e-12) << name;
    EXPECT_NEAR(w.state(0).p_WBo.z(), 12 * t - 0.5 * 9.81 * t * t, 1e-12) << name;
    EXPECT_NEAR(w.state(0).v_WBo.z(), 12 - 9.81 * t, 1e-12) << name;
  }
}

// Semi-implicit Euler on a constant acceleration: z_n = z0 + v0 t + g t^2 / 2 + g h t / 2 exactly.
TEST(Analytic, SemiImplicitEulerProjectileIsItsPredictedDiscreteResult) {
  const double h = 1.0 / 60;
  for (const std::string name : {"games103", "implicit_gyro"}) {
    World w(projectile(name, h));
    w.step(120);
    const double t = w.time();
    EXPECT_NEAR(w.state(0).p_WBo.z(), 12 * t - 0.5 * 9.81 * t * t - 0.5 * 9.81 * h * t, 1e-12)
        << name;
  }
  // Explicit Euler lags by the same amount the other way.
  World w(projectile("notes_explicit_euler", h));
  w.step(120);
  const double t = w.time();
  EXPECT_NEAR(w.state(0).p_WBo.z(), 12 * t - 0.5 * 9.81 * t * t + 0.5 * 9.81 * h * t, 1e-12);
}

// v' = g - (c/m) v: v(t) = v_inf + (v0 - v_inf) e^{-ct/m}, x(t) = v_inf t + (v0 - v_inf) m/c (1 -
// e^{-ct/m}). The exact splitting reproduces it at any c dt / m, here 5.
TEST(Analytic, LinearDragDecaysExactly) {
  const double m = 2.0, c = 10.0, h = 1.0;  // c h / m = 5
  BodySpec b = body("d", {1, 1, 1});
  b.mass = m;
  b.linear_drag = c;
  b.use_gravity = true;
  b.v_WBo = {4, 0, 0};
  for (const std::string name : {"exact_rotor4", "exact_rotor"}) {
    WorldSpec ws = one_body(b, h, name);
    ws.g_W = {0, 0, -9.81};
    World w(ws);
    const double v_inf = -9.81 * m / c;
    for (int k = 1; k <= 6; ++k) {
      w.step();
      const double t = w.time(), e = std::exp(-c * t / m);
      EXPECT_NEAR(w.state(0).v_WBo.x(), 4 * e, 1e-14) << name;
      EXPECT_NEAR(w.state(0).p_WBo.x(), 4 * m / c * (1 - e), 1e-14) << name;
      EXPECT_NEAR(w.state(0).v_WBo.z(), v_inf * (1 - e), 1e-14) << name;
      EXPECT_NEAR(w.state(0).p_WBo.z(), v_inf * t - v_inf * m / c * (1 - e), 1e-13) << name;
    }
  }
}

// Spin about a principal axis: w constant, orientation exp(w t), for every gyroscopic scheme.
TEST(Analytic, SpinAboutAPrincipalAxis) {
  for (const std::string name : {"exact_rotor4", "exact_rotor", "rk4", "dlm", "implicit_gyro"}) {
    for (int axis = 0; axis < 3; ++axis) {
      World w(one_body(body("s", {1, 2, 3}, 6.0 * Vec3::Unit(axis)), 1e-3, name));
      w.step(1000);
      const Quat expect(Eigen::AngleAxisd(6.0, Vec3::Unit(axis)));
      const double tol = name == "rk4" ? 1e-11 : 1e-12;
      EXPECT_LT(angle_between(w.state(0).q_WB, expect), tol) << name << " axis " << axis;
      EXPECT_LT((w.state(0).w_WB - 6.0 * Vec3::Unit(axis)).norm(), 1e-12) << name;
    }
  }
}

// The torque of a force at a lever arm is (R r) x f: checked on the course notes' scheme, whose
// first step from rest is w_W = h I_W^-1 ((R r) x f) exactly, for a world-frame force and for a
// body-frame force (which turns with the body: f_W = R f_B).
TEST(Analytic, TorqueOfAForceAtALeverArmInBothFrames) {
  const Quat R(Eigen::AngleAxisd(0.9, Vec3(1, -2, 0.5).normalized()));
  const Vec3 I(1, 2, 3), r(0.3, -0.1, 0.2), f(2, 5, -1);
  const double h = 1e-3;
  for (Frame frame : {Frame::kWorld, Frame::kBody}) {
    BodySpec b = body("t", I);
    b.q_WB = R;
    WorldSpec ws = one_body(b, h, "games103");
    ws.loads.push_back(LoadSpec{.body = 0, .force = f, .p_BoQ_B = r, .frame = frame});
    World w(ws);
    w.step();
    const Vec3 f_W = frame == Frame::kWorld ? f : Vec3(R * f);
    const Vec3 tau_W = (R * r).cross(f_W);
    const physics::Mat3 Rm = R.toRotationMatrix();
    const Vec3 expect = h * (Rm * I.asDiagonal().inverse() * Rm.transpose()) * tau_W;
    EXPECT_LT((w.state(0).w_WB - expect).norm(), 4e-15 * expect.norm());
    EXPECT_LT((w.state(0).v_WBo - h * f_W).norm(), 1e-16);
  }
}

// The same lever-arm torque over a whole trajectory, body-frame and world-frame forces together,
// against the independent long-double reference: every gyroscopic scheme converges to it.
TEST(Analytic, ForcesAtPointsFollowTheReferenceTrajectory) {
  const Vec3 I(1, 2, 3);
  BodySpec b = body("t", I, {0.5, -1, 2});
  WorldSpec ws = one_body(b, 1e-3, "");
  ws.loads.push_back(
      LoadSpec{.body = 0, .force = {0, 0, 2}, .p_BoQ_B = {0.5, 0, 0}, .frame = Frame::kBody});
  ws.loads.push_back(
      LoadSpec{.body = 0, .force = {1, 0, 0}, .p_BoQ_B = {0, 0.3, 0}, .frame = Frame::kWorld});
  RefBody rb;
  rb.I = to_ld(I);
  rb.f_B = V3(0, 0, 2), rb.r_fB = V3(0.5, 0, 0);
  rb.f_W = V3(1, 0, 0), rb.r_fW = V3(0, 0.3, 0);
  RefState rs;
  rs.w = V3(0.5, -1, 2);
  ref_run(rb, rs, 2.0, 200000);
  for (const std::string name : {"exact_rotor4", "rk4"}) {
    ws.integrator = name;
    World w(ws);
    w.step(2000);
    EXPECT_LT(angle_between(w.state(0).q_WB, to_double(rs.q)), 1e-9) << name;
    EXPECT_LT((w.state(0).p_WBo - to_double(rs.x)).norm(), 1e-9) << name;
  }
}

// Free precession of an axisymmetric body (A, A, C): w3 constant, the transverse part of w_B
// turning at Omega = (C - A) w3 / A, and L_W fixed.
TEST(Analytic, AxisymmetricFreePrecession) {
  const double A = 1.0, C = 1.8;
  const Vec3 w0(1.2, -0.4, 3.0);
  const double Omega = (C - A) * w0.z() / A;
  for (const std::string name : {"exact_rotor4", "exact_rotor", "rk4"}) {
    World w(one_body(body("top", {A, A, C}, w0), 1e-3, name));
    const Vec3 L0 = w.angular_momentum_W(0);
    w.step(3000);
    const double t = w.time();
    const BodyState s = w.state(0);
    const Vec3 w_B = s.q_WB.conjugate() * s.w_WB;
    const Vec3 expect(std::cos(Omega * t) * w0.x() - std::sin(Omega * t) * w0.y(),
                      std::sin(Omega * t) * w0.x() + std::cos(Omega * t) * w0.y(), w0.z());
    EXPECT_LT((w_B - expect).norm(), 1e-10) << name;
    EXPECT_LT((w.angular_momentum_W(0) - L0).norm(), 1e-10) << name;
  }
}

}  // namespace
}  // namespace rigid::test
