// The batched kernels (server/physics/hybrid_lanes.hpp, rotor_lanes.hpp, iso_lanes.hpp): every
// kernel width the CPU runs gives the same states bit for bit, with bodies of every load kind, with
// and without drag, slow and fast (the series and the libm branches mixed inside one batch), and a
// run whose length is no multiple of any width (padded batches); a body steps to the same bits
// alone as in a batch with others; free bodies step bit for bit as the scalar code steps them
// (RIGID_LANES=1), loaded ones to its round-off; plans moved by a regroup too. The store of the
// general bodies' plans (rotor_plans.hpp) gives back what the pinned step reads, of either sign,
// its blocks are ready exactly when all their entries are, and general bodies stepped by the
// kernel match the independent long-double reference (not merely the scalar code, which reads
// the same store).
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "physics/hybrid_lanes.hpp"
#include "physics/rotor_plans.hpp"
#include "test_util.hpp"

namespace rigid::test {
namespace {

using physics::BodyState;
using physics::Frame;
using physics::LoadSpec;

// General and axisymmetric bodies (the kernel's groups), each with a load that keeps it in the
// loaded run: a body-fixed thruster, a world force at a lever, a world torque; some with angular
// or linear drag; every fifth spinning fast enough (|w| dt / 2 > 1/16) for cos_sinc's libm
// branch: about the middle axis (a tumbling flip, which magnifies any difference: fine for
// comparisons bit for bit), or with `stable`, about a stable axis (for comparisons to round-off).
WorldSpec loaded(int n, bool stable = false) {
  WorldSpec ws;
  ws.dt = 1e-3;
  ws.integrator = "hybrid4";
  ws.g_W = {0, 0, -9.81};
  for (int i = 0; i < n; ++i) {
    const double e = 1e-2 * (i % 13);
    // Moments in runs, so that batches of one shared rotational entry (model.hpp: Shared)
    // follow batches of another, and of several.
    const double eI = 1e-2 * (i / 8 % 3);
    const Vec3 I = i % 2 == 0 ? Vec3(1, 2 + eI, 3) : Vec3(1, 1, 0.4 + eI);
    const double spin = i % 5 == 2 ? 300.0 : 5.0;
    const Vec3 w = stable ? Vec3(0.1 - e, 0.3 + e, spin) : Vec3(0.3 + e, spin, 0.1 - e);
    BodySpec b = body("b" + std::to_string(i), I, w);
    if (i % 7 == 3) b.angular_drag = 0.05;
    // Runs of bodies with and without linear drag (two translation tables' rows; a batch may
    // hold one or both).
    if (i % 16 >= 11) b.linear_drag = 0.3 + 0.1 * (i % 2);
    // Runs of heavier bodies: batches of one shared translation entry (Group::linears) follow
    // batches of another, and of several.
    if (i / 8 % 2 == 1) b.mass = 2.0;
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

// Every body's state, by id.
std::vector<BodyState> states(const World& w) {
  std::vector<BodyState> out;
  for (int i = 0; i < w.body_count(); ++i)
    out.push_back(w.state(i));
  return out;
}

// Steps ws; halfway, an impulse on body `kick` if >= 0 (the cached plans and runs change).
std::vector<BodyState> run(const WorldSpec& ws, int steps, int kick = -1) {
  World w(ws);
  for (int k = 0; k < steps; ++k) {
    if (k == steps / 2 && kick >= 0) w.apply_impulse(kick, {0, 0, 0.1}, {0.1, 0, 0}, Frame::kBody);
    w.step();
  }
  return states(w);
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

// Free bodies of every model (general, isotropic, axisymmetric, point masses: i % 4), with what
// a quiet body may carry: gravity, linear drag, a force at its centre of mass; slow and fast spins
// (a fast one takes the free rotor's long step, which stays scalar; general bodies at three rates,
// one per quadrature rule of a cached plan, and both ways). Gravity and drag come in
// runs (of 10 bodies of a model), so that the translation kernel takes runs of bodies sharing
// their parameters whole and breaks them where they change; one point mass carries a
// body-fixed force (its group's loaded run). 23 isotropic bodies: a remainder after fours.
WorldSpec free_bodies(int n, const std::string& integrator) {
  WorldSpec ws;
  ws.dt = 1e-3;
  ws.integrator = integrator;
  for (int i = 0; i < n; ++i) {
    const double e = 1e-2 * (i % 7);
    const Vec3 I = i % 4 == 0   ? Vec3(1, 2 + e, 3)
                   : i % 4 == 1 ? Vec3(0.4, 0.4, 0.4)
                                : Vec3(1, 1, 1.8);
    // General bodies at 5, 20 and 60 rad/s, mixed in every block: the cached plans' 2-, 3- and
    // 4-node rules (|X| = 0.003, 0.012, 0.035 at 1 ms); one (the second block's fourth) at
    // 400 rad/s, a long step (no nodes), whose block the kernel must leave to the scalar code
    // (block_ready), while the first block steps in the kernel.
    const double spin = i % 8 == 1 || i == 44 ? 400.0
                        : i % 4 != 0          ? 5.0
                        : i / 4 % 3 == 0      ? 5.0
                        : i / 4 % 3 == 1      ? 20.0
                                              : 60.0;
    BodySpec b = body("f" + std::to_string(i), I, {1e-3 + e, spin, 1e-3});
    // Every other general body spins the other way: plans of both signs s in every block.
    if (i % 8 == 4) b.w_WB = -b.w_WB;
    b.has_inertia = i % 4 != 3;
    b.use_gravity = i / 40 % 2 == 0;
    if (i >= 60 && i < 70) b.linear_drag = 0.3;
    b.v_WBo = {e, -1, 0.5};
    ws.bodies.push_back(b);
    if (i % 6 == 1) ws.loads.push_back(LoadSpec{.body = i, .force = {0.5, 0, 2}});
  }
  ws.loads.push_back(
      LoadSpec{.body = 7, .force = {0, 1, 0}, .p_BoQ_B = {0, 0, 0}, .frame = Frame::kBody});
  return ws;
}

// The states `go` gives at each kernel width this CPU runs (RIGID_LANES=8, 4, 2; a width it
// cannot run falls back to a narrower one: the width taken is given beside them), and with the
// scalar code (RIGID_LANES=1).
struct ByWidth {
  std::vector<std::pair<int, std::vector<BodyState>>> lanes;
  std::vector<BodyState> scalar;
};
template <class Go>
ByWidth by_width(const Go& go) {
  ByWidth r;
  for (const char* w : {"8", "4", "2"}) {
    const LanesEnv env(w);
    r.lanes.emplace_back(physics::detail::pick_lane_width(), go());
  }
  const LanesEnv env("1");
  EXPECT_EQ(physics::detail::pick_lane_width(), 1);
  r.scalar = go();
  return r;
}

TEST(Lanes, FreeBodiesStepBitForBitAsTheScalarCode) {
  for (const char* integrator : {"hybrid4", "exact_rotor4", "exact_rotor"}) {
    const WorldSpec ws = free_bodies(90, integrator);
    const ByWidth r = by_width([&] { return run(ws, 500); });
    for (const auto& [width, lanes] : r.lanes) {
      for (std::size_t i = 0; i < lanes.size(); ++i)
        EXPECT_TRUE(same_bits(lanes[i], r.scalar[i]))
            << integrator << ", width " << width << ", body " << i;
    }
  }
}

// The quiet translation reads no force while no quiet body of its group has one in W
// (Group::quiet_pushed). Forces in W start and stop on a point mass, and a sphere reaches the
// quiet run with one from the loaded run (a body-fixed force at a lever, then one in W through its
// centre), while no other quiet sphere has a force: the kernel must read forces exactly while some
// quiet body has one, so every width steps bit for bit as the scalar code, which always reads them.
TEST(Lanes, ForcesInWThatComeAndGoOnQuietBodiesAreNeverMissed) {
  WorldSpec ws;
  ws.dt = 1e-3;
  ws.integrator = "hybrid4";
  ws.g_W = {0, 0, -9.81};
  for (int i = 0; i < 40; ++i) {
    BodySpec b = body("q" + std::to_string(i), Vec3(0.4, 0.4, 0.4), {0.3, 2.0 + 0.1 * i, -0.2});
    b.has_inertia = i % 2 == 0;  // spheres and point masses
    b.use_gravity = true;
    b.v_WBo = {0.1, -1, 0.5};
    ws.bodies.push_back(b);
  }
  constexpr int kSphere = 10, kPoint = 11;
  const auto run_pushed = [&] {
    World w(ws);
    for (int k = 0; k < 400; ++k) {
      if (k == 100) w.add_force(kSphere, {1, 0, 3}, {0, 0.2, 0}, Frame::kBody);  // loaded
      if (k == 120) w.add_force(kPoint, {0, 2, 0}, {0, 0, 0}, Frame::kWorld);    // quiet, pushed
      if (k == 200) {  // to the quiet run with its force
        w.clear_applied(kSphere);
        w.add_force(kSphere, {1, 0, 3}, {0, 0, 0}, Frame::kWorld);
      }
      if (k == 250) w.clear_applied(kPoint);
      if (k == 300) w.clear_applied(kSphere);
      w.step();
    }
    return states(w);
  };
  const ByWidth r = by_width(run_pushed);
  const std::vector<BodyState>& scalar = r.scalar;
  // The forces acted: the pushed bodies left their free twins' velocities (2-3 N on 1 kg for
  // 0.13-0.2 s: ~0.3-0.6 m/s).
  EXPECT_GT((scalar[kSphere].v_WBo - scalar[kSphere - 2].v_WBo).norm(), 0.1);
  EXPECT_GT((scalar[kPoint].v_WBo - scalar[kPoint - 2].v_WBo).norm(), 0.1);
  for (const auto& [width, lanes] : r.lanes) {
    for (std::size_t i = 0; i < lanes.size(); ++i)
      EXPECT_TRUE(same_bits(lanes[i], scalar[i])) << "width " << width << ", body " << i;
  }
}

TEST(Lanes, LoadedBodiesMatchTheScalarCompositionToRoundOff) {
  const WorldSpec ws = loaded(29, true);
  const std::vector<BodyState> lanes = run(ws, 400, 1);
  const LanesEnv env("1");
  const std::vector<BodyState> scalar = run(ws, 400, 1);
  for (std::size_t i = 0; i < lanes.size(); ++i) {
    // The same composition, its products and sums grouped differently: round-off apart (growing
    // with the angle turned, 120 rad for the fast ones), where a wrong term would be off by far
    // more (one step's torque alone moves w by ~1e-4).
    const double turned = scalar[i].w_WB.norm() * 0.4;
    EXPECT_LT(lanes[i].q_WB.angularDistance(scalar[i].q_WB), 1e-12 * (1 + turned)) << "body " << i;
    EXPECT_LT((lanes[i].w_WB - scalar[i].w_WB).norm(), 1e-9 * (1 + scalar[i].w_WB.norm()))
        << "body " << i;
    EXPECT_LT((lanes[i].p_WBo - scalar[i].p_WBo).norm(), 1e-11) << "body " << i;
  }
}

// The general bodies' plans are stored eight to a block, field by field (rotor_plans.hpp): what
// RotorUpdate::kPinned reads comes back bit for bit (a short step's nodes, a long step's closed
// form in their place), what it does not read comes back NaN, a plan from the store steps bit for
// bit as the plan set, a swap exchanges two entries whole, the kernel's view of a block holds each
// entry's fields in its lane, and lane_ready says which plans the kernel may step. Plans of every
// kind: both cases, short steps (quadrature nodes) and long ones (closed form and panels), a still
// body.
TEST(RotorPlans, StoreWhatThePinnedStepReadsBitForBit) {
  using physics::RotorPlan;
  using physics::detail::RotorPlans;
  const auto bits = [](double v) { return std::bit_cast<std::uint64_t>(v); };
  const auto same = [&](const RotorPlan& x, const RotorPlan& y) {
    bool ok = x.still == y.still && x.case_b == y.case_b && x.n == y.n;
    // A still plan is nothing more (advance_rotor reads no other field of it).
    if (y.still) return ok;
    for (auto [u, v] : {std::pair{x.s, y.s},
                        {x.a, y.a},
                        {x.b, y.b},
                        {x.c, y.c},
                        {x.ia, y.ia},
                        {x.ib, y.ib},
                        {x.cn_bias, y.cn_bias},
                        {x.m, y.m},
                        {x.mc, y.mc},
                        {x.G, y.G},
                        {x.lin, y.lin},
                        {x.abG2, y.abG2},
                        {x.cG, y.cG},
                        {x.S, y.S},
                        {x.C, y.C},
                        {x.D, y.D},
                        {x.mS2, y.mS2},
                        {x.mSC, y.mSC}})
      ok = ok && bits(u) == bits(v);
    // Only RotorUpdate::kIncrement reads these: not kept (x is the store's).
    ok = ok && std::isnan(x.ic) && std::isnan(x.Cm1) && std::isnan(x.Dm1);
    ok = ok && bits(x.X) == bits(y.X);
    // The nodes past n are not read: NaN (a long step has none).
    for (int k = y.n; k < 4; ++k)
      ok = ok && std::isnan(x.w[k]) && std::isnan(x.Dn[k]) && std::isnan(x.mS2n[k]) &&
           std::isnan(x.mSCn[k]);
    if (y.n > 0) {
      // The weights made again from X and the rule of n nodes.
      for (int k = 0; k < y.n; ++k)
        ok = ok && bits(x.w[k]) == bits(y.w[k]) && bits(x.Dn[k]) == bits(y.Dn[k]) &&
             bits(x.mS2n[k]) == bits(y.mS2n[k]) && bits(x.mSCn[k]) == bits(y.mSCn[k]);
      for (double v : {x.q, x.isr, x.sq, x.qm3, x.K, x.Jc})
        ok = ok && std::isnan(v);
    } else {
      ok = ok && x.closed == y.closed;
      for (auto [u, v] : {std::pair{x.q, y.q},
                          {x.isr, y.isr},
                          {x.sq, y.sq},
                          {x.qm3, y.qm3},
                          {x.K, y.K},
                          {x.Jc, y.Jc}})
        ok = ok && bits(u) == bits(v);
    }
    return ok;
  };
  // One pinned step from momentum m with each plan: the same bits.
  const auto steps_alike = [&](const RotorPlan& x, const RotorPlan& y, const Vec3& m) {
    Vec3 mx = m, my = m;
    Quat dx, dy;
    physics::advance_rotor(x, mx, dx, physics::RotorUpdate::kPinned);
    physics::advance_rotor(y, my, dy, physics::RotorUpdate::kPinned);
    bool ok = true;
    for (int k = 0; k < 3; ++k)
      ok = ok && bits(mx[k]) == bits(my[k]);
    for (int k = 0; k < 4; ++k)
      ok = ok && bits(dx.coeffs()[k]) == bits(dy.coeffs()[k]);
    return ok;
  };
  const physics::RotorInertia J(Vec3(1.0, 2.0, 3.0));
  std::vector<RotorPlan> made;
  std::vector<Vec3> from;
  for (int i = 0; i < 29; ++i) {
    // Momenta about each axis (case a and b), near the separatrix, and zero; steps from 1 ms to
    // 30 s (long steps: no nodes), and 20 ms (four nodes).
    Vec3 m = i == 7 ? Vec3::Zero()
                    : Vec3(0.3 + 0.1 * (i % 3), (i % 2 ? 5.0 : 0.2) + 0.01 * i,
                           (i % 2 ? 0.1 : 4.0) - 0.003 * i);
    // Both signs s = sign(m3) of the polhode (free_rotor.cpp): a third of the momenta turned
    // round, another third only in their third component.
    if (i % 3 == 1) m = -m;
    if (i % 3 == 2) m.z() = -m.z();
    const double h = i % 4 == 3 ? 30.0 : i % 6 == 5 ? 0.02 : 1e-3 * (1 + i % 5);
    RotorPlan p;
    physics::make_rotor_plan(J, m, h, p);
    made.push_back(p);
    from.push_back(m);
  }
  ASSERT_TRUE(std::any_of(made.begin(), made.end(), [](auto& p) { return p.case_b; }));
  ASSERT_TRUE(std::any_of(made.begin(), made.end(), [](auto& p) { return !p.case_b; }));
  ASSERT_TRUE(std::any_of(made.begin(), made.end(), [](auto& p) { return p.n == 0 && !p.still; }));
  ASSERT_TRUE(std::any_of(made.begin(), made.end(), [](auto& p) { return p.n == 0 && p.closed; }));
  for (int n : {2, 3, 4})  // each rule's weights
    ASSERT_TRUE(std::any_of(made.begin(), made.end(), [n](auto& p) { return p.n == n; })) << n;
  ASSERT_TRUE(std::any_of(made.begin(), made.end(), [](auto& p) { return p.still; }));
  for (double s : {-1.0, 1.0}) {
    for (bool long_step : {true, false})  // long steps and short ones of either sign
      ASSERT_TRUE(
          std::any_of(made.begin(), made.end(),
                      [&](auto& p) { return !p.still && p.s == s && (p.n == 0) == long_step; }))
          << s << " " << long_step;
  }

  RotorPlans store;
  for (std::size_t i = 0; i < made.size(); ++i)
    store.push_back();
  ASSERT_EQ(store.size(), static_cast<int>(made.size()));
  for (std::size_t i = 0; i < made.size(); ++i)
    store.set(static_cast<int>(i), made[i]);
  for (std::size_t i = 0; i < made.size(); ++i) {
    const int k = static_cast<int>(i);
    EXPECT_TRUE(same(store.get(k), made[i])) << "entry " << i;
    EXPECT_TRUE(steps_alike(store.get(k), made[i], from[i])) << "entry " << i;
    EXPECT_EQ(store.lane_ready(k), !made[i].still && made[i].n > 0) << "entry " << i;
    const auto& L = store.lanes(k / RotorPlans::kBlock);
    const int l = k % RotorPlans::kBlock;
    const unsigned f = store.flags(k / RotorPlans::kBlock)[l];
    EXPECT_EQ((f & physics::detail::kRotorFlagCaseB) != 0, made[i].case_b);
    EXPECT_EQ((f & physics::detail::kRotorFlagStill) != 0, made[i].still);
    EXPECT_EQ(static_cast<int>(f & physics::detail::kRotorFlagNodes), made[i].n);
    if (!made[i].still) {
      EXPECT_EQ((f & physics::detail::kRotorFlagNegative) != 0, made[i].s < 0.0);
    }
    EXPECT_EQ(bits(L.k2[l]), bits(made[i].m));
    EXPECT_EQ(bits(L.iG[l]), bits(made[i].iG));
    EXPECT_EQ(bits(L.X[l]), bits(made[i].X));
    if (made[i].n == 4) {
      EXPECT_EQ(bits(L.mSCn[3][l]), bits(made[i].mSCn[3]));
    }
  }
  // Across blocks and within one.
  for (auto [a, b] : {std::pair{3, 20}, {0, 1}, {28, 8}}) {
    store.swap(a, b);
    std::swap(made[static_cast<std::size_t>(a)], made[static_cast<std::size_t>(b)]);
    std::swap(from[static_cast<std::size_t>(a)], from[static_cast<std::size_t>(b)]);
  }
  for (std::size_t i = 0; i < made.size(); ++i) {
    EXPECT_TRUE(same(store.get(static_cast<int>(i)), made[i])) << "after swaps, entry " << i;
    EXPECT_TRUE(steps_alike(store.get(static_cast<int>(i)), made[i], from[i]))
        << "after swaps, entry " << i;
  }
}

// block_ready says in one pass over a block's flags what lane_ready says of each of its eight
// entries: short steps of every rule (2, 3 and 4 nodes: flags bits 0b010, 0b011, 0b100) are
// ready; one long step (no nodes) or one still plan keeps its whole block out of the kernel.
TEST(RotorPlans, ABlockIsReadyWhenEveryEntryIs) {
  using physics::RotorPlan;
  using physics::detail::RotorPlans;
  const physics::RotorInertia J(Vec3(1.0, 2.0, 3.0));
  const auto plan = [&](const Vec3& m, double h) {
    RotorPlan p;
    physics::make_rotor_plan(J, m, h, p);
    return p;
  };
  const Vec3 m(0.3, 5.0, -0.2);
  // At 1 ms, 5 ms and 20 ms this momentum's plans take 2, 3 and 4 nodes; at 30 s none.
  const RotorPlan two = plan(m, 1e-3), three = plan(m, 5e-3), four = plan(m, 2e-2);
  const RotorPlan long_step = plan(m, 30.0), still = plan(Vec3::Zero(), 1e-3);
  ASSERT_EQ(two.n, 2);
  ASSERT_EQ(three.n, 3);
  ASSERT_EQ(four.n, 4);
  ASSERT_EQ(long_step.n, 0);
  ASSERT_FALSE(long_step.still);
  ASSERT_TRUE(still.still);
  const RotorPlan* ready[3] = {&two, &three, &four};
  RotorPlans store;
  std::vector<bool> expect;
  // Per block: every entry ready, then one entry made a long step or still, in each lane in turn.
  const int blocks = 1 + 2 * RotorPlans::kBlock;
  for (int b = 0; b < blocks; ++b) {
    bool all = true;
    for (int l = 0; l < RotorPlans::kBlock; ++l) {
      const int i = store.size();
      store.push_back();
      const RotorPlan* p = ready[(b + l) % 3];
      if (b > 0 && (b - 1) % RotorPlans::kBlock == l)
        p = b <= RotorPlans::kBlock ? &long_step : &still;
      store.set(i, *p);
      all = all && store.lane_ready(i);
    }
    expect.push_back(all);
  }
  EXPECT_TRUE(expect[0]);
  for (int b = 0; b < blocks; ++b) {
    EXPECT_EQ(store.block_ready(b), expect[static_cast<std::size_t>(b)]) << "block " << b;
    if (b > 0) {
      EXPECT_FALSE(expect[static_cast<std::size_t>(b)]) << "block " << b;
    }
  }
}

// General bodies stepped by the lanes kernel in full blocks (16 alike but for their spins'
// signs and sizes: both signs s of the polhode in every block, and a pure spin) against the
// independent long-double reference: what the store keeps of a plan and the kernel reads of it is
// checked against physics, not against the same store read by the scalar code.
TEST(Lanes, GeneralBodiesOfEitherSignMatchTheReference) {
  WorldSpec ws;
  ws.dt = 1e-3;
  ws.integrator = "hybrid4";
  const Vec3 I(1.0, 2.0, 3.0);
  std::vector<Vec3> w0;
  for (int i = 0; i < 2 * physics::detail::RotorPlans::kBlock; ++i) {
    // Case a (about the axis of greatest inertia) and case b (least), at 1 to 8 rad/s.
    Vec3 w = i % 2 == 0 ? Vec3(0.3, 0.2, 2.0 + 0.5 * (i / 2)) : Vec3(2.0 + 0.5 * (i / 2), 0.2, 0.3);
    if (i % 4 >= 2) w.z() = -w.z();
    if (i % 8 >= 4) w = -w;
    // A pure spin about the axis of greatest inertia in each block (a = 0: cn_bias = 1).
    if (i % 8 == 5) w = Vec3(0.0, 0.0, i < 8 ? 3.0 : -3.0);
    w0.push_back(w);
    ws.bodies.push_back(body("g" + std::to_string(i), I, w));
  }
  World w(ws);
  const double T = 0.5;
  w.step(static_cast<int>(std::lround(T / ws.dt)));
  for (std::size_t i = 0; i < w0.size(); ++i) {
    const int id = static_cast<int>(i);
    ASSERT_EQ(w.body_motion(id), physics::BodyMotion::kTumbling);
    const RefState ref = free_reference(I, w0[i], T, 20000);
    const Quat q_ref = to_double(ref.q);
    const Vec3 w_ref_W = q_ref * to_double(ref.w);
    EXPECT_LT(angle_between(w.state(id).q_WB, q_ref), 1e-11) << "body " << i;
    EXPECT_LT((w.state(id).w_WB - w_ref_W).norm(), 1e-11 * w_ref_W.norm()) << "body " << i;
  }
}

// Bodies that leave the quiet run and come back (a controller pushes them, then lets go) swap
// their cached plans with others (World's regroup: RotorPlans::swap, through get and set), which
// leaves NaN in the nodes past n of the plans moved: the kernel must step blocks mixing 2-, 3-
// and 4-node plans so moved exactly as the scalar code does, which reads only n nodes.
TEST(Lanes, PlansMovedByARegroupStepBitForBitAsTheScalarCode) {
  const WorldSpec ws = free_bodies(90, "hybrid4");
  static constexpr int kPushed[] = {0, 8, 16, 36, 52};
  const auto go = [&] {
    World w(ws);
    w.step(50);
    for (int k = 0; k < 60; ++k) {
      // General bodies (i % 4 == 0) pushed at a lever in turns, some for a step, some for many.
      for (int id : kPushed) {
        if (k % (id / 4 + 2) == 0) w.add_force(id, {0.0, 0.3, 1.0}, {0.2, 0.0, 0.1}, Frame::kBody);
        if (k % (id / 4 + 2) == 1) w.clear_applied(id);
      }
      w.step();
    }
    w.clear_applied();
    w.step(200);
    return states(w);
  };
  const ByWidth r = by_width(go);
  const std::vector<BodyState>& scalar = r.scalar;
  for (const auto& [width, lanes] : r.lanes) {
    for (std::size_t i = 0; i < lanes.size(); ++i) {
      if (std::count(std::begin(kPushed), std::end(kPushed), static_cast<int>(i)) == 0) {
        EXPECT_TRUE(same_bits(lanes[i], scalar[i])) << "width " << width << ", body " << i;
      } else {
        // While pushed, a body steps in the loaded kernel: the scalar code's round-off.
        EXPECT_LT(angle_between(lanes[i].q_WB, scalar[i].q_WB), 1e-12)
            << "width " << width << ", body " << i;
        EXPECT_LT((lanes[i].w_WB - scalar[i].w_WB).norm(), 1e-12 * scalar[i].w_WB.norm())
            << "width " << width << ", body " << i;
      }
    }
  }
  for (const BodyState& s : scalar)
    EXPECT_TRUE(s.q_WB.coeffs().allFinite() && s.w_WB.allFinite());
}

}  // namespace
}  // namespace rigid::test
