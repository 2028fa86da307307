// The measured order of convergence of every integrator on a smooth forced case is within 0.3 of
// its theory. The case has everything at once: gravity, a body-frame force at a lever arm, a
// world-frame force at another point, linear and angular drag, and a spin whose moments differ.
// The course notes' schemes have no gyroscopic term, so they are measured on a sphere, the body
// for which their dynamics are the true ones.
#include <gtest/gtest.h>

#include <cmath>

#include "test_util.hpp"

namespace rigid::test {
namespace {

using physics::Frame;
using physics::LoadSpec;

constexpr double kT = 1.0;

struct Case {
  Vec3 I;
  RefState ref;
};

WorldSpec forced(const Vec3& I, double dt, const std::string& integrator) {
  BodySpec b = body("b", I, {0.8, -0.5, 1.2});
  b.mass = 1.5;
  b.use_gravity = true;
  b.linear_drag = 0.3;
  b.angular_drag = 0.1;
  b.v_WBo = {1, 0, 2};
  WorldSpec ws = one_body(b, dt, integrator);
  ws.g_W = {0, 0, -9.81};
  ws.loads.push_back(
      LoadSpec{.body = 0, .force = {0, 0, 1}, .p_BoQ_B = {0.5, 0, 0}, .frame = Frame::kBody});
  ws.loads.push_back(
      LoadSpec{.body = 0, .force = {0.5, 0, 0}, .p_BoQ_B = {0, 0.3, 0}, .frame = Frame::kWorld});
  return ws;
}

RefState reference(const Vec3& I) {
  RefBody rb;
  rb.I = to_ld(I);
  rb.mass = 1.5;
  rb.c = 0.3;
  rb.k = 0.1;
  rb.g = V3(0, 0, -9.81);
  rb.f_B = V3(0, 0, 1), rb.r_fB = V3(0.5, 0, 0);
  rb.f_W = V3(0.5, 0, 0), rb.r_fW = V3(0, 0.3, 0);
  RefState s;
  s.w = V3(0.8, -0.5, 1.2);
  s.v = V3(1, 0, 2);
  ref_run(rb, s, kT, 100000);
  return s;
}

double error(const std::string& integrator, const Vec3& I, const RefState& ref, int n) {
  World w(forced(I, kT / n, integrator));
  w.step(n);
  const physics::BodyState s = w.state(0);
  return angle_between(s.q_WB, to_double(ref.q)) + (s.p_WBo - to_double(ref.x)).norm() +
         (s.v_WBo - to_double(ref.v)).norm() +
         (s.w_WB - to_double(ref.q) * to_double(ref.w)).norm();
}

TEST(Convergence, EveryIntegratorHasItsOrder) {
  const Vec3 general(1, 2, 3), sphere(0.7, 0.7, 0.7);
  const RefState ref_general = reference(general), ref_sphere = reference(sphere);
  for (const auto& info : physics::all_integrators()) {
    const std::string name(info.name);
    const bool sphere_only = !info.gyroscopic;
    const Vec3& I = sphere_only ? sphere : general;
    const RefState& ref = sphere_only ? ref_sphere : ref_general;
    // Step counts in each method's asymptotic range, far above round-off.
    const int n0 = info.order == 1 ? 200 : info.order == 2 ? 50 : 10;
    const double e1 = error(name, I, ref, n0), e2 = error(name, I, ref, 2 * n0),
                 e3 = error(name, I, ref, 4 * n0);
    const double p = std::log2(e2 / e3);
    EXPECT_NEAR(p, info.order, 0.3) << name << ": errors " << e1 << " " << e2 << " " << e3;
    EXPECT_LT(e3, e1) << name;
  }
}

}  // namespace
}  // namespace rigid::test

namespace rigid::test {
namespace {

// The default's loaded path on each body model it has one for (general: split drift; axisymmetric:
// closed-form precession; isotropic: exact rotation), and its Suzuki-composed candidate: order 4.
TEST(Convergence, Hybrid4IsFourthOrderOnEveryModel) {
  for (const Vec3& I : {Vec3(1, 2, 3), Vec3(1, 1, 2), Vec3(0.7, 0.7, 0.7), Vec3(0.5, 1.0, 1.3)}) {
    const RefState ref = reference(I);
    for (const std::string name : {"hybrid4", "hybrid4_suzuki"}) {
      const double e1 = error(name, I, ref, 10), e2 = error(name, I, ref, 20),
                   e3 = error(name, I, ref, 40);
      EXPECT_NEAR(std::log2(e2 / e3), 4.0, 0.3)
          << name << " I = " << I.transpose() << ": errors " << e1 << " " << e2 << " " << e3;
    }
  }
}

}  // namespace
}  // namespace rigid::test
