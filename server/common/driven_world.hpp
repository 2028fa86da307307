// A physics World driven by wrench commands and edits one tick at a time: the table of acting
// wrenches, the world's applied loads rebuilt from it before each tick, and the tick counter. The
// loop (loop.hpp) drives its world through this class, and rigid-sim --replay drives its own
// through it too, so a replay applies each journaled wrench and edit exactly as the live loop did:
// the same table, the same order of summation, the same expiry, the same arithmetic on a state
// edit. Nothing here knows about time, threads or buses.
#pragma once

#include <cstdint>
#include <vector>

#include "common/applied_command.hpp"
#include "common/wrench_table.hpp"
#include "physics/world.hpp"

namespace rigid::common {

class DrivenWorld {
 public:
  // tick_dt: the tick period (1 / rate_hz), which turns a wrench's ttl into ticks; substeps:
  // physics steps per tick; wrench_capacity: acting wrenches at most.
  DrivenWorld(const physics::WorldSpec& spec, double tick_dt, int substeps,
              std::size_t wrench_capacity);

  // A validated wrench: it acts from the next tick for ticks_to_live(ttl) ticks, replacing the
  // one with the same (source, body, key). kFull: a new key and no room; nothing changed.
  // Into the wrench table, against `sender`'s share (wrench_table.hpp). A replay (rigid-sim
  // --replay) applies journaled wrenches with an unlimited share: they were accepted once.
  WrenchTable::Upsert apply(const Wrench& wrench, std::uint64_t sender = 0,
                            std::size_t share = SIZE_MAX);
  // One tick: loads the acting wrenches (in arrival order) into the world, runs `substeps`
  // physics steps, advances the tick and drops the wrenches that have expired. Allocation-free.
  void step_tick();
  // The next step_tick comes within `within_ns`: the world's step threads get ready for it
  // (World::expect_step). Changes no state.
  void expect_tick(std::int64_t within_ns) { world_.expect_step(within_ns); }
  // The scene's initial state at tick 0, with no wrenches.
  void reset();
  // A validated edit, between two ticks. kSetState: the parts it sets replace the body's (a
  // velocity in the body frame turned by the orientation the body has after the edit), the
  // others stay; the world re-applies the body's frozen axes. kResetBody: the body's scene state,
  // and the wrenches acting on it dropped. Either way a body the guard froze stays frozen (a
  // world reset thaws it); the state reads back to round-off (the world keeps a body's rotation
  // in its principal frame). Allocates only to copy a reset body's scene entry
  // (World::body_spec) when its name is longer than std::string keeps inline (15 characters).
  void edit(const Edit& edit);
  // Does ahead the first-step work of the next tick (World::prepare_step: the caches a world
  // makes on its first step and after a reset). Changes no state.
  int prepare_tick() { return world_.prepare_step(); }

  std::int64_t tick() const { return tick_; }
  const physics::World& world() const { return world_; }
  std::size_t wrench_count() const { return wrenches_.size(); }
  std::size_t wrench_capacity() const { return wrenches_.capacity(); }
  double tick_dt() const { return tick_dt_; }
  int substeps() const { return substeps_; }

 private:
  void load_wrenches();
  void clear_loaded();

  physics::World world_;
  double tick_dt_;
  int substeps_;
  WrenchTable wrenches_;
  std::int64_t tick_ = 0;
  // Bodies that hold applied loads from the last rebuild (capacity: every wrench on its own body),
  // and a per-body mark so that each is listed once: the rebuild clears just these, not every
  // body of the world (30-60 us a tick with 10^4 bodies).
  std::vector<int> loaded_;
  std::vector<std::uint8_t> is_loaded_;
};

}  // namespace rigid::common
