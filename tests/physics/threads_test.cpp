// World::step on a pool of threads, and the regrouping of bodies whose loads start or stop: the
// states are bit-identical for any thread count and across runs, a body's trajectory does not
// depend on the other bodies or on where it sits in its model's arrays, and stepping allocates
// nothing.
#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <bit>
#include <chrono>
#include <cstring>
#include <limits>
#include <string>
#include <thread>
#include <vector>

#include "allocation_counter.hpp"
#include "physics/pool.hpp"
#include "test_util.hpp"

namespace rigid::test {
namespace {

using physics::BodyState;
using physics::Frame;
using physics::LoadSpec;

// Bodies of all four models, spread a little; some carry a constant load (a body-fixed thruster
// or a world force at a lever), some drag, the others none.
WorldSpec crowd(int n, const std::string& integrator, int threads) {
  WorldSpec ws;
  ws.dt = 1e-3;
  ws.integrator = integrator;
  ws.threads = threads;
  ws.g_W = {0, 0, -9.81};
  for (int i = 0; i < n; ++i) {
    const double e = 1e-3 * (i % 97);
    const Vec3 I = i % 4 == 0   ? Vec3(1, 2, 3)
                   : i % 4 == 1 ? Vec3(1, 1, 0.4)
                   : i % 4 == 2 ? Vec3(0.7, 0.7, 0.7)
                                : Vec3(0.5, 1.0, 1.3);
    BodySpec b = body("b" + std::to_string(i), I, {0.3 + e, -0.2, 2.0 + 10 * e});
    if (i % 11 == 5) b.has_inertia = false;
    b.use_gravity = i % 2 == 0;
    if (i % 13 == 3) b.angular_drag = 0.05;
    if (i % 17 == 4) b.linear_drag = 0.4;
    b.v_WBo = {e, 1, 0};
    ws.bodies.push_back(b);
    if (i % 3 == 0) {
      ws.loads.push_back(
          LoadSpec{.body = i, .force = {0, 0, 4}, .p_BoQ_B = {0.4, 0.1, 0}, .frame = Frame::kBody});
    } else if (i % 5 == 1) {
      ws.loads.push_back(LoadSpec{.body = i, .force = {0, 0, -9.81}, .p_BoQ_B = {0, 0, 0.3}});
    }
  }
  return ws;
}

// Drives a world through a run in which applied loads start and stop on some bodies (every 10
// steps the set changes), with an impulse now and then.
void drive(World& w, int steps) {
  for (int k = 0; k < steps; ++k) {
    if (k % 10 == 0) {
      w.clear_applied();
      for (int i = k % 7; i < w.body_count(); i += 7)
        w.add_torque(i, {0.1, -0.2, 0.05 * (k % 3)}, Frame::kBody);
      for (int i = k % 5; i < w.body_count(); i += 19)
        w.add_force(i, {1, 0, 0}, {0, 0.2, 0}, Frame::kWorld);
    }
    if (k % 25 == 7) w.apply_impulse(k % w.body_count(), {0, 0, 0.1}, {0.1, 0, 0}, Frame::kBody);
    // As rigidd's loop does before a tick: the workers wake ahead of the step (no state changes).
    if (k % 3 == 1) w.expect_step(50'000);
    w.step();
  }
}

// A body's state as the rows of World::write_states hold it: p_WBo, q_WB (w first), v_WBo, w_WB.
std::array<double, 13> values(const BodyState& s) {
  return {s.p_WBo.x(), s.p_WBo.y(), s.p_WBo.z(), s.q_WB.w(), s.q_WB.x(), s.q_WB.y(), s.q_WB.z(),
          s.v_WBo.x(), s.v_WBo.y(), s.v_WBo.z(), s.w_WB.x(), s.w_WB.y(), s.w_WB.z()};
}

std::uint64_t hash_of(const World& w) {
  std::uint64_t h = 1469598103934665603ull;  // FNV-1a over every body's state bytes
  for (int i = 0; i < w.body_count(); ++i) {
    for (double v : values(w.state(i))) {
      std::uint64_t bits;
      std::memcpy(&bits, &v, sizeof bits);
      h = (h ^ bits) * 1099511628211ull;
    }
  }
  return h;
}

TEST(WorldThreads, StatesAreBitIdenticalForAnyThreadCount) {
  // 8 threads of at least kMinBodiesPerThread bodies each: every count below really splits.
  const int n = 8 * World::kMinBodiesPerThread + 37;
  // Every integrator's kernel (each splits its own loops over the shares), and the default.
  std::vector<std::string> names{""};
  for (const physics::IntegratorInfo& info : physics::all_integrators())
    names.emplace_back(info.name);
  for (const std::string& integrator : names) {
    std::uint64_t first = 0;
    for (int threads : {1, 2, 3, 8, 1}) {
      World w(crowd(n, integrator, threads));
      EXPECT_EQ(w.threads(), threads);
      drive(w, 60);
      w.step(25);  // steps back to back: the pool's workers poll between them (pool.hpp)
      drive(w, 10);
      const std::uint64_t h = hash_of(w);
      if (first == 0) first = h;
      EXPECT_EQ(h, first) << "'" << integrator << "' with " << threads << " threads";
    }
  }
}

// write_states on the step's threads (a world of several kBodiesPerWriteChunk chunks): every
// row is state(id)'s, bit for bit, and every row is written, for any thread count; and writing
// allocates nothing.
TEST(WorldThreads, WriteStatesOnThreadsIsStateOfEveryBody) {
  const int n = 3 * World::kBodiesPerWriteChunk + 101;
  const auto bits = [](double x) { return std::bit_cast<std::uint64_t>(x); };
  for (int threads : {1, 2, 3, 8}) {
    World w(crowd(n, "", threads));
    drive(w, 12);  // loads start and stop: the models' entries are out of id order
    const auto k = static_cast<std::size_t>(n);
    // NaN-filled, so that a row left unwritten fails the comparison below.
    const double nan = std::numeric_limits<double>::quiet_NaN();
    std::vector<double> p(3 * k, nan), q(4 * k, nan), v(3 * k, nan), o(3 * k, nan);
    const long before = allocation_count();
    w.write_states({p.data(), q.data(), v.data(), o.data()});
    EXPECT_EQ(allocation_count(), before) << threads << " threads";
    for (int i = 0; i < n; ++i) {
      const auto r = static_cast<std::size_t>(i);
      const std::array<double, 13> want = values(w.state(i));
      const std::array<double, 13> got{
          p[3 * r], p[3 * r + 1], p[3 * r + 2], q[4 * r], q[4 * r + 1], q[4 * r + 2], q[4 * r + 3],
          v[3 * r], v[3 * r + 1], v[3 * r + 2], o[3 * r], o[3 * r + 1], o[3 * r + 2]};
      for (std::size_t j = 0; j < want.size(); ++j)
        ASSERT_EQ(bits(got[j]), bits(want[j]))
            << "body " << i << " value " << j << ", " << threads << " threads";
    }
  }
}

// The pool behind World::step: every chunk of every run is run exactly once and all of them are
// done when run() returns, whether the workers poll between runs or sleep and wake late (the
// caller may then have claimed a whole run alone and published the next one before they look),
// and whether the caller said a run was coming (expect_run: the workers wake and poll for it) in
// time, too late, or for a run that came after the workers had given up polling.
TEST(Pool, RunsEveryChunkOnceAndAllBeforeReturning) {
  struct Ctx {
    std::array<std::atomic<int>, 64> calls{};
    std::atomic<int> slow{-1};  // this chunk takes a while (another thread must take the rest)
  } ctx;
  for (int threads : {2, 3}) {
    physics::detail::Pool pool(threads);
    for (int run = 0; run < 3000; ++run) {
      const int chunks = 1 + (run * 7) % 64;
      for (auto& c : ctx.calls)
        c.store(0, std::memory_order_relaxed);
      ctx.slow.store(run % 5 == 0 ? run % chunks : -1, std::memory_order_relaxed);
      if (run % 6 == 2) pool.expect_run((run % 4) * 50'000);
      if (run % 11 == 5) {  // announced, then late: the workers poll 20 us and sleep
        pool.expect_run(0);
        std::this_thread::sleep_for(std::chrono::microseconds(60));
      }
      pool.run(
          [](void* p, int c) {
            Ctx& x = *static_cast<Ctx*>(p);
            if (c == x.slow.load(std::memory_order_relaxed))
              std::this_thread::sleep_for(std::chrono::microseconds(50));
            x.calls[static_cast<std::size_t>(c)].fetch_add(1, std::memory_order_relaxed);
          },
          &ctx, chunks, run % 3 == 1);
      for (int c = 0; c < 64; ++c)
        ASSERT_EQ(ctx.calls[static_cast<std::size_t>(c)].load(), c < chunks ? 1 : 0)
            << "chunk " << c << " of " << chunks << ", run " << run << ", " << threads
            << " threads";
      // Now and then a pause, so that the workers go to sleep and wake late for the next run.
      if (run % 4 == 0) std::this_thread::sleep_for(std::chrono::microseconds(40 * (run % 3)));
    }
  }
}

TEST(WorldThreads, SetThreadsMidRunAndCopies) {
  const int n = 4 * World::kMinBodiesPerThread;
  World a(crowd(n, "", 1)), b(crowd(n, "", 3));
  drive(a, 30);
  drive(b, 30);
  b.set_threads(2);
  World c = b;  // a copy gets a pool of its own
  EXPECT_EQ(c.threads(), 2);
  // The workers a caller may place (rigidd keeps them off its loop's CPU): threads - 1 of them,
  // each World its own.
  EXPECT_TRUE(a.worker_threads().empty());
  ASSERT_EQ(b.worker_threads().size(), 1u);
  ASSERT_EQ(c.worker_threads().size(), 1u);
  EXPECT_NE(b.worker_threads()[0], c.worker_threads()[0]);
  drive(a, 30);
  drive(b, 30);
  drive(c, 30);
  EXPECT_EQ(hash_of(a), hash_of(b));
  EXPECT_EQ(hash_of(a), hash_of(c));
  EXPECT_THROW(a.set_threads(-1), std::invalid_argument);
  WorldSpec bad = crowd(4, "", 1);
  bad.threads = -2;
  EXPECT_THROW(World{bad}, physics::SpecError);
  a.set_threads(0);
  EXPECT_GE(a.threads(), 1);
}

TEST(WorldThreads, SteppingAllocatesNothing) {
  World w(crowd(4 * World::kMinBodiesPerThread, "", 3));
  w.step(2);
  const long before = allocation_count();
  drive(w, 40);
  w.step(40);
  EXPECT_EQ(allocation_count(), before);
}

// A copy keeps what stepping relies on having reserved (a copied vector does not keep its
// capacity): giving loads to every body at once, impulses to every body and stepping allocate
// nothing in a copy either.
TEST(WorldThreads, ACopySteppingAllocatesNothing) {
  const World original(crowd(2 * World::kMinBodiesPerThread, "", 2));
  World w = original;
  World assigned(crowd(3, "", 1));
  assigned = original;
  for (World* c : {&w, &assigned}) {
    c->step(2);
    const long before = allocation_count();
    for (int round = 0; round < 3; ++round) {
      for (int i = 0; i < c->body_count(); ++i) {
        c->add_force(i, {0, 0, 1}, {0.1, 0, 0}, Frame::kBody);
        c->add_force(i, {1, 0, 0}, {0, 0.2, 0}, Frame::kWorld);
        c->apply_impulse(i, {0, 0, 0.1}, {0.1, 0, 0}, Frame::kBody);
      }
      c->step(3);
      c->clear_applied();
      c->step(2);
    }
    EXPECT_EQ(allocation_count(), before);
  }
}

// World::prepare_step makes ahead exactly the caches the next step would make first: the quiet
// isotropic, axisymmetric and general bodies', for the integrators that cache their exact drift,
// once each until something makes them stale, without allocating.
TEST(WorldPrepareStep, MakesEachStaleCacheOfAQuietBodyOnce) {
  const auto spec = [](const std::string& integrator, int threads) {
    WorldSpec ws;
    ws.dt = 1e-3;
    ws.integrator = integrator;
    ws.threads = threads;
    ws.g_W = {0, 0, -9.81};
    // 300 each (a world large enough to split over threads): 0 point masses, 1 isotropic, 2
    // axisymmetric, 3 general, all quiet; 4 general with a thruster, 5 axisymmetric with drag.
    for (int i = 0; i < 6 * 300; ++i) {
      const int kind = i % 6;
      const Vec3 I = kind == 1                ? Vec3(2, 2, 2)
                     : kind == 2 || kind == 5 ? Vec3(1, 1, 1.5)
                                              : Vec3(1, 2, 3);
      BodySpec b = body("b" + std::to_string(i), I, {0.3 + 1e-3 * i, -0.2, 2.0});
      b.has_inertia = kind != 0;
      if (kind == 5) b.angular_drag = 0.05;
      ws.bodies.push_back(b);
      if (kind == 4) {
        ws.loads.push_back(LoadSpec{
            .body = i, .force = {0, 0, 4}, .p_BoQ_B = {0.4, 0.1, 0}, .frame = Frame::kBody});
      }
    }
    return ws;
  };
  const int quiet = 3 * 300;
  for (const physics::IntegratorInfo& info : physics::all_integrators()) {
    const bool caches = info.id == physics::IntegratorId::kExactRotor ||
                        info.id == physics::IntegratorId::kExactRotor4 ||
                        info.id == physics::IntegratorId::kHybrid4;
    for (int threads : {1, 3}) {
      SCOPED_TRACE(std::string(info.name) + " on " + std::to_string(threads) + " threads");
      World w(spec(std::string(info.name), threads));
      const long before = allocation_count();
      EXPECT_EQ(w.prepare_step(), caches ? quiet : 0);
      EXPECT_EQ(w.prepare_step(), 0);  // nothing stale any more
      w.step(3);
      EXPECT_EQ(w.prepare_step(), 0);  // the steps kept them
      // set_state makes one body's stale (a general body: id 3).
      BodyState s = w.state(3);
      s.w_WB.x() += 0.1;
      w.set_state(3, s);
      EXPECT_EQ(w.prepare_step(), caches ? 1 : 0);
      // A body pushed for a while, then let go: its cache went stale while it was loaded, and it
      // is back among the quiet ones (an isotropic body: id 7).
      w.add_torque(7, {0, 0.5, 0}, Frame::kBody);
      w.step(2);
      EXPECT_EQ(w.prepare_step(), 0);  // loaded: it caches nothing
      w.clear_applied(7);
      EXPECT_EQ(w.prepare_step(), caches ? 1 : 0);
      w.step();
      w.reset();
      EXPECT_EQ(w.prepare_step(), caches ? quiet : 0);
      EXPECT_EQ(allocation_count(), before);
      EXPECT_EQ(w.step_count(), 0);
    }
  }
}

// What prepare_step makes is what the step would have made: a world prepared before its first
// step and whenever loads, states or a reset made caches stale steps to the very bits of one that
// never is, for every integrator and thread count.
TEST(WorldPrepareStep, ChangesNoState) {
  constexpr int n = 3 * World::kMinBodiesPerThread + 37;
  std::vector<std::string> names{""};
  for (const physics::IntegratorInfo& info : physics::all_integrators())
    names.emplace_back(info.name);
  const auto run = [](const std::string& integrator, int threads, bool prepare) {
    World w(crowd(n, integrator, threads));
    std::vector<std::uint64_t> hashes;
    for (int round = 0; round < 3; ++round) {
      if (prepare) w.prepare_step();
      drive(w, 20);
      if (prepare) w.prepare_step();
      w.step(5);
      BodyState s = w.state(round);
      s.w_WB += Vec3(0.2, 0, -0.1);
      w.set_state(round, s);
      if (prepare) w.prepare_step();
      drive(w, 15);
      hashes.push_back(hash_of(w));
      if (round == 1) {
        w.reset();
        if (prepare) w.prepare_step();
      }
    }
    return hashes;
  };
  for (const std::string& integrator : names) {
    const std::vector<std::uint64_t> plain = run(integrator, 1, false);
    for (int threads : {1, 3}) {
      EXPECT_EQ(run(integrator, threads, true), plain)
          << "'" << integrator << "' with " << threads << " threads";
    }
  }
}

// A body's trajectory is the same alone and in a crowd whose other bodies' loads start and stop
// (so that it changes place in its model's arrays many times), for every body model.
TEST(WorldRegroup, ABodyMovesBetweenRunsWithoutChangingItsTrajectory) {
  const int n = 300;
  const WorldSpec ws = crowd(n, "", 2);
  World all(ws);
  // 7 and 23: quiet general bodies whose moments differ from body 0's (their own rotor constants).
  for (int id : {0, 1, 2, 3, 5, 7, 16, 21, 23}) {
    WorldSpec one = ws;
    one.bodies = {ws.bodies[id]};
    one.loads.clear();
    for (LoadSpec l : ws.loads) {
      if (l.body == id) one.loads.push_back((l.body = 0, l));
    }
    World alone(one);
    all = World(ws);
    for (int k = 0; k < 60; ++k) {
      if (k % 10 == 0) {
        all.clear_applied();
        alone.clear_applied();
        for (int i = k % 7; i < n; i += 7) {
          all.add_torque(i, {0.1, -0.2, 0.05 * (k % 3)}, Frame::kBody);
          if (i == id) alone.add_torque(0, {0.1, -0.2, 0.05 * (k % 3)}, Frame::kBody);
        }
      }
      all.step();
      alone.step();
    }
    const BodyState a = all.state(id), b = alone.state(0);
    EXPECT_EQ(a.q_WB.coeffs(), b.q_WB.coeffs()) << id;
    EXPECT_EQ(a.w_WB, b.w_WB) << id;
    EXPECT_EQ(a.p_WBo, b.p_WBo) << id;
    EXPECT_EQ(a.v_WBo, b.v_WBo) << id;
  }
}

// The default on a body nothing turns is the exact free rotor: bit for bit exact_rotor4's step.
TEST(Hybrid4, FreeBodiesTakeTheExactRotorStep) {
  for (const Vec3& I : {Vec3(1, 2, 3), Vec3(1, 1, 1.8), Vec3(0.4, 0.4, 0.4)}) {
    World a(one_body(body("r", I, {1e-3, 5, 1e-3}), 1e-3, "hybrid4"));
    World b(one_body(body("r", I, {1e-3, 5, 1e-3}), 1e-3, "exact_rotor4"));
    a.step(20000);
    b.step(20000);
    EXPECT_EQ(a.state(0).q_WB.coeffs(), b.state(0).q_WB.coeffs()) << I.transpose();
    EXPECT_EQ(a.state(0).w_WB, b.state(0).w_WB) << I.transpose();
  }
}

}  // namespace
}  // namespace rigid::test
