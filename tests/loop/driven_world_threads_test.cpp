// The loop's world on a pool of threads (rigidd --threads, world { threads }): a scene with
// constant loads on some bodies, driven tick by tick by wrenches that start, replace each other
// and expire on a third of the bodies (the way controllers push in rigidd), gives bit-identical
// published states, by the journal's state hash, for 1, 2, 3 and 8 threads. The physics-level
// test (tests/physics/threads_test.cpp) drives World directly; this one goes through
// common::DrivenWorld, the wrench table and the state frame, which rigidd and rigid-sim --replay
// share.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "common/driven_world.hpp"
#include "common/state_conversion.hpp"
#include "common/state_hash.hpp"

namespace rigid::loop {
namespace {

using physics::BodySpec;
using physics::LoadSpec;
using physics::Vec3;
using physics::WorldSpec;

// Enough bodies that 8 threads each get more than World::kMinBodiesPerThread (every count splits).
constexpr int kBodies = 8 * physics::World::kMinBodiesPerThread + 101;
constexpr double kTickDt = 1e-3;

WorldSpec scene(int threads, int bodies = kBodies) {
  WorldSpec ws;
  ws.dt = kTickDt;
  ws.threads = threads;
  for (int i = 0; i < bodies; ++i) {
    BodySpec b;
    b.name = "b" + std::to_string(i);
    const double e = 1e-3 * (i % 89);
    // General, axisymmetric, isotropic bodies and point masses.
    const Vec3 I = i % 4 == 0   ? Vec3(1, 2, 3)
                   : i % 4 == 1 ? Vec3(1, 1, 0.4)
                   : i % 4 == 2 ? Vec3(0.7, 0.7, 0.7)
                                : Vec3(0.5, 1.0, 1.3 + e);
    b.I_B = I.asDiagonal();
    b.has_inertia = i % 9 != 4;
    b.w_WB = {0.3 + e, -2.0, 5.0 + 10 * e};
    b.v_WBo = {e, 1, 0};
    b.angular_drag = i % 13 == 3 ? 0.05 : 0.0;
    ws.bodies.push_back(b);
    if (i % 7 == 2) {  // a thruster fixed to the body, off its centre of mass
      ws.loads.push_back(LoadSpec{
          .body = i, .force = {0, 0, 3}, .p_BoQ_B = {0.4, 0.1, 0}, .frame = physics::Frame::kBody});
    }
  }
  return ws;
}

// Runs `ticks` ticks; every 5 ticks a new round of wrenches (a third of the bodies, each wrench
// with its own ttl, so that some expire between rounds). The state hash after every tick, folded.
std::uint64_t run(int threads, int ticks, int bodies = kBodies) {
  common::DrivenWorld driven(scene(threads, bodies), kTickDt, 1,
                             std::max<std::size_t>(4096, bodies));
  EXPECT_EQ(driven.world().threads(), threads);
  rigid::StateFrame frame;
  common::shape_state_frame(driven.world(), frame);
  std::uint64_t folded = 0;
  for (int t = 0; t < ticks; ++t) {
    if (t % 5 == 0) {
      for (int body = t % 3; body < bodies; body += 3) {
        Wrench w;
        w.source = 1;
        w.seq = t * bodies + body;
        w.key = 0;
        w.body = body;
        w.force = {0.5 * (body % 5), -1.0, 0.25 * (t % 4)};
        w.point = {0.1, 0.0, -0.2};
        w.force_frame = body % 2 == 0 ? rigid::Frame::kWorld : rigid::Frame::kBody;
        if (body % 4 == 1) w.torque = {0.0, 0.2, -0.1};
        w.ttl = 1e-3 * (body % 8);
        EXPECT_NE(driven.apply(w), common::WrenchTable::Upsert::kFull);
      }
    }
    driven.step_tick();
    common::fill_state_frame(driven.world(), driven.tick(), driven.world().time(), frame);
    folded = folded * 1099511628211ull ^ common::state_hash(frame);
  }
  return folded;
}

TEST(DrivenWorldThreads, PublishedStatesAreBitIdenticalFor1To8Threads) {
  const std::uint64_t one = run(1, 60);
  for (int threads : {2, 3, 8}) {
    EXPECT_EQ(run(threads, 60), one) << threads << " threads";
  }
  // A run that differs in one wrench differs in its hash: the comparison can fail.
  common::DrivenWorld a(scene(2), kTickDt, 1, 16), b(scene(2), kTickDt, 1, 16);
  Wrench w;
  w.body = 17;
  w.force = {1, 0, 0};
  a.apply(w);
  a.step_tick();
  b.step_tick();
  rigid::StateFrame fa, fb;
  common::shape_state_frame(a.world(), fa);
  common::shape_state_frame(b.world(), fb);
  common::fill_state_frame(a.world(), 1, a.world().time(), fa);
  common::fill_state_frame(b.world(), 1, b.world().time(), fb);
  EXPECT_NE(common::state_hash(fa), common::state_hash(fb));
}

// A world large enough that its state frames are written on the world's threads too
// (World::write_states, two chunks of kBodiesPerWriteChunk and more): the same frames for 1, 2
// and 3 threads. Here rather than only in tests/physics because this directory also runs under
// ThreadSanitizer.
TEST(DrivenWorldThreads, LargeWorldsStateFramesAreBitIdenticalFor1To3Threads) {
  constexpr int kLarge = 2 * physics::World::kBodiesPerWriteChunk + 57;
  const std::uint64_t one = run(1, 6, kLarge);
  for (int threads : {2, 3}) {
    EXPECT_EQ(run(threads, 6, kLarge), one) << threads << " threads";
  }
}

}  // namespace
}  // namespace rigid::loop
