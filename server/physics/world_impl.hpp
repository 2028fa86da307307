// World's inside, shared by the files that implement it, one concern each:
//   world_build.cpp   building the Model and the Data from a WorldSpec, in named stages;
//   world_groups.cpp  where a body's entry is, its loads, and moving it between its group's runs;
//   world_step.cpp    the step's stages, the threads that run them, and the guard;
//   world_access.cpp  states, loads and impulses in and out, and every other accessor.
// The Model is built once and shared, constant, by the World and its copies; each copy has its
// own Data.
#pragma once

#include <algorithm>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "physics/data.hpp"
#include "physics/kernels.hpp"
#include "physics/model.hpp"
#include "physics/pool.hpp"
#include "physics/world.hpp"

namespace rigid::physics {

struct World::Impl {
  std::shared_ptr<const detail::Model> model_ptr;
  detail::Data data;
  // The step's threads and their shares of the work (set_threads).
  int threads = 1;
  std::vector<detail::Share> shares;
  struct PoolHandle {
    std::unique_ptr<detail::Pool> pool;
    PoolHandle() = default;
    PoolHandle(PoolHandle&&) noexcept = default;
    PoolHandle& operator=(PoolHandle&&) noexcept = default;
    // A copied World gets a pool of its own.
    PoolHandle(const PoolHandle& o)
        : pool(o.pool ? std::make_unique<detail::Pool>(o.pool->size()) : nullptr) {}
    PoolHandle& operator=(const PoolHandle& o) {
      if (this != &o) pool = o.pool ? std::make_unique<detail::Pool>(o.pool->size()) : nullptr;
      return *this;
    }
  } pool;

  const detail::Model& model() const { return *model_ptr; }
  int body_count() const { return static_cast<int>(data.entry.size()); }
  void check_id(int id) const {
    if (id < 0 || id >= body_count()) {
      throw std::out_of_range("no body with id " + std::to_string(id));
    }
  }

  // --- world_build.cpp ---
  // The stages validate, classify and intern, then these two.
  void build(const WorldSpec& spec);
  void build_loads(const WorldSpec& spec, detail::Model& model);
  void place_bodies(int threads_wanted);
  // A copied vector keeps its elements but not its capacity: what stepping relies on having
  // reserved (no allocation while stepping) is reserved again in a copy.
  void reserve_scratch();

  // --- world_groups.cpp ---
  // f(group view, entry) for body id's group and entry in it: the view's kind is a compile-time
  // constant inside f (detail::visit).
  template <class F>
  decltype(auto) with_body(int id, F&& f) {
    return detail::visit(model().motion[id], [&](auto k) -> decltype(auto) {
      return f(detail::group(model(), data, k), static_cast<int>(data.entry[id]));
    });
  }
  template <class F>
  decltype(auto) with_body(int id, F&& f) const {
    return detail::visit(model().motion[id], [&](auto k) -> decltype(auto) {
      return f(detail::group(model(), data, k), static_cast<int>(data.entry[id]));
    });
  }
  detail::Motion& motion(int id) {
    return with_body(id, [](auto g, int i) -> detail::Motion& { return g.motion(i); });
  }
  const detail::Motion& motion(int id) const {
    return with_body(id, [](auto g, int i) -> const detail::Motion& { return g.motion(i); });
  }
  const detail::Linear& linear(int id) const {
    return with_body(id, [](auto g, int i) -> const detail::Linear& { return g.linear(i); });
  }
  detail::LoadsRef load(int id) const {
    return with_body(id, [](auto g, int i) { return g.load(i); });
  }
  detail::Loads load_value(int id) const {
    return with_body(id, [](auto g, int i) { return g.entries.load_value(i); });
  }
  void set_loads(int id, const detail::Loads& v, std::int32_t shared_terms = 0) {
    // A body the contact stage holds or schedules by its loads is looked at again when they
    // change (a value written again, as clear_applied() does every tick, changes nothing).
    if (model().contact.enabled() && !same_loads(load_value(id), v)) contact_wake(id);
    with_body(id, [&](auto g, int i) { g.entries.set_load(i, v, shared_terms); });
  }
  static bool same_loads(const detail::Loads& a, const detail::Loads& b) {
    return a.flags == b.flags && a.f_W == b.f_W && a.f_P == b.f_P && a.tau_P == b.tau_P &&
           a.tau_W == b.tau_W && a.fr == b.fr;
  }
  // Body id's loads back to the scene's (SceneLoads entry b, or none: -1), its terms shared.
  void set_scene_loads(int id, int b);
  // Called after anything that may change whether a body's loads leave it quiet.
  void loads_changed(int id, bool was_quiet) {
    if (load(id).quiet() != was_quiet && !data.regroup_flag[id]) {
      data.regroup_flag[id] = 1;
      data.regroup_ids.push_back(id);  // within the reserved capacity
    }
  }
  // Puts body id in the run of its group that its loads call for; every body that may have moved.
  void place(int id);
  void regroup();
  // Body id's exact-drift cache is stale (its momentum changed).
  void invalidate_cache(int id);

  // --- world_step.cpp ---
  void set_threads(int n);
  // The most chunks a step is cut into (World::kChunksPerThread; what the pool can count).
  int max_chunks() const {
    return static_cast<int>(
        std::min<long>(long{kChunksPerThread} * threads, detail::Pool::kMaxChunks));
  }
  // How many chunks this world's steps are cut into (1: the calling thread alone).
  int step_parts() const;
  void plan_shares(int parts);
  // Runs fn(impl, share) for every share [0, parts), over the pool when there is more than one.
  void run_parts(int parts, void (*fn)(Impl&, detail::Share&), bool another_follows);
  void run_share(detail::Share& sh);
  void step(bool another_follows);
  int prepare_step();
  void apply_pending_impulses();
  // The guard's check of the bodies whose turn it is after step data.steps (World::guard_phase).
  void guard();
  // The ids [begin, end) checked at phase k (0 .. kGuardEvery - 1).
  std::pair<int, int> guard_slice(int k) const {
    const long n = body_count();
    const int j = (k + kGuardEvery - 1) % kGuardEvery;
    return {static_cast<int>(n * j / kGuardEvery), static_cast<int>(n * (j + 1) / kGuardEvery)};
  }
  void freeze(int id);
  void thaw_all();

  // --- world_contact.cpp ---
  // The static parts and each body's collision shape and surface into the Model; the Data's
  // contact state to its start (every body free and due at the first step).
  void build_contacts(const WorldSpec& spec, detail::Model& model);
  void reset_contacts();
  void reserve_contacts();
  // Body id's loads, state or momentum changed: a held body is let go, and it is looked at in the
  // next step; after set_state it is free until the stage finds what it touches.
  void contact_wake(int id);
  void contact_state_set(int id);
  // Before the kernels: the bodies the stage looks at this step, and their motion at its start.
  void contact_prepare();
  // After the kernels: each of those bodies' step with its contacts.
  void contact_stage();
  void after_free(int id);
  void hold(int id);

  // --- world_pairs.cpp ---
  // Bodies against bodies: the broad phase, this step's islands, and each island's step.
  void motion_bounds(int id, double& speed, double& accel) const;
  void broad_phase();
  void pairs_prepare();
  void pairs_stage();
  void wake_group(int group);
  const detail::Motion& start_of(int id) const;
  template <class F>
  decltype(auto) with_moving(int id, F&& f);
  contact::Pose pose_of(int id) const;
  int island_contacts(std::span<const int> ids, double margin, detail::IslandContact* out, int cap);
  void island_step(std::span<const int> ids);
  bool island_impacts(std::span<const int> ids, double time, double left,
                      detail::IslandContact* touching, int cap);
  void island_time_step(std::span<const int> ids, double h, double time,
                        detail::IslandContact* touching, int cap);
  void warm_start(const detail::IslandContact& t, double h, std::size_t first);
  void push_event(const ContactEvent& e);

  // --- world_access.cpp ---
  void set_state(int id, const BodyState& s);
  // q_BP of body id: the identity for the groups whose P is B.
  Quat rot_BP(int id) const;
  Vec3 angular_momentum_P(int id) const;
  Vec3 omega_P(int id) const;
};

}  // namespace rigid::physics
