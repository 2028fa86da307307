// hybrid4's batched kernel for loaded bodies (server/physics/hybrid_lanes.hpp): every kernel width
// the CPU runs gives the same states bit for bit, with bodies of every load kind, with and without
// drag, slow and fast (the series and the libm branches mixed inside one batch), and a run whose
// length is no multiple of any width (padded batches); a body steps to the same bits alone as in a
// batch with others.
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "physics/hybrid_lanes.hpp"
#include "test_util.hpp"

namespace rigid::test {
namespace {

using physics::BodyState;
using physics::Frame;
using physics::LoadSpec;

// General and axisymmetric bodies (the kernel's groups), each with a load that keeps it in the
// loaded run: a body-fixed thruster, a world force at a lever, a world torque; some with angular
// drag; every fifth spinning fast enough (|w| dt / 2 > 1/16) for cos_sinc's libm branch.
WorldSpec loaded(int n) {
  WorldSpec ws;
  ws.dt = 1e-3;
  ws.integrator = "hybrid4";
  ws.g_W = {0, 0, -9.81};
  for (int i = 0; i < n; ++i) {
    const double e = 1e-2 * (i % 13);
    const Vec3 I = i % 2 == 0 ? Vec3(1, 2 + e, 3) : Vec3(1, 1, 0.4 + e);
    const double spin = i % 5 == 2 ? 300.0 : 5.0;
    BodySpec b = body("b" + std::to_string(i), I, {0.3 + e, spin, 0.1 - e});
    if (i % 7 == 3) b.angular_drag = 0.05;
    b.use_gravity = i % 2 == 1;
    b.v_WBo = {e, 1, 0};
    ws.bodies.push_back(b);
    switch (i % 3) {
      case 0:
        ws.loads.push_back(LoadSpec{
            .body = i, .force = {0, 0, 4}, .p_BoQ_B = {0.4, 0.1, 0}, .frame = Frame::kBody});
        break;
      case 1:
        ws.loads.push_back(LoadSpec{.body = i, .force = {1, 0, -9.81}, .p_BoQ_B = {0, 0.2, 0.3}});
        break;
      default:
        ws.loads.push_back(LoadSpec{.body = i, .torque = {0.2, -0.1, 0.3}});
        break;
    }
  }
  return ws;
}

// Steps ws; halfway, an impulse on body `kick` if >= 0 (the cached plans and runs change).
std::vector<BodyState> run(const WorldSpec& ws, int steps, int kick = -1) {
  World w(ws);
  for (int k = 0; k < steps; ++k) {
    if (k == steps / 2 && kick >= 0) w.apply_impulse(kick, {0, 0, 0.1}, {0.1, 0, 0}, Frame::kBody);
    w.step();
  }
  std::vector<BodyState> out;
  for (int i = 0; i < w.body_count(); ++i)
    out.push_back(w.state(i));
  return out;
}

bool same_bits(const BodyState& a, const BodyState& b) {
  const auto eq = [](const auto& x, const auto& y) {
    return std::memcmp(x.data(), y.data(), sizeof(double) * x.size()) == 0;
  };
  return eq(a.p_WBo, b.p_WBo) && eq(a.v_WBo, b.v_WBo) && eq(a.w_WB, b.w_WB) &&
         eq(a.q_WB.coeffs(), b.q_WB.coeffs());
}

// Sets RIGID_LANES for the worlds built in its scope.
struct LanesEnv {
  explicit LanesEnv(const char* w) { ::setenv("RIGID_LANES", w, 1); }
  ~LanesEnv() { ::unsetenv("RIGID_LANES"); }
};

TEST(Hybrid4Lanes, EveryKernelWidthGivesTheSameStates) {
  const int widest = physics::detail::pick_lane_width();
  ASSERT_TRUE(widest == 2 || widest == 4 || widest == 8) << widest;
  const WorldSpec ws = loaded(8 * 3 + 5);  // 29: padded batches at every width
  const std::vector<BodyState> ref = run(ws, 400, 1);
  for (const char* w : {"2", "4"}) {
    if (std::atoi(w) > widest) continue;  // this CPU cannot run it: nothing to compare
    const LanesEnv env(w);
    ASSERT_EQ(physics::detail::pick_lane_width(), std::atoi(w));
    const std::vector<BodyState> got = run(ws, 400, 1);
    for (std::size_t i = 0; i < ref.size(); ++i)
      EXPECT_TRUE(same_bits(got[i], ref[i])) << "body " << i << " with " << w << " lanes";
  }
  // The bodies really moved and turned (the comparison is not of untouched states).
  const BodyState fast = ref[2];
  EXPECT_GT(fast.w_WB.norm(), 100.0);
  EXPECT_GT((ref[0].p_WBo - ws.bodies[0].p_WBo).norm(), 0.1);
}

TEST(Hybrid4Lanes, ABodyAloneStepsAsInABatch) {
  const WorldSpec ws = loaded(21);
  const std::vector<BodyState> all = run(ws, 300);
  for (int id : {0, 1, 2, 3, 7, 20}) {
    WorldSpec one = ws;
    one.bodies = {ws.bodies[id]};
    one.loads.clear();
    for (LoadSpec l : ws.loads) {
      if (l.body == id) one.loads.push_back((l.body = 0, l));
    }
    const std::vector<BodyState> alone = run(one, 300);
    EXPECT_TRUE(same_bits(alone[0], all[id])) << "body " << id;
  }
}

}  // namespace
}  // namespace rigid::test
