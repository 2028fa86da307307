// A body's entry in its group (groups.hpp), and moving it between the group's two runs: each
// group's entries are its quiet bodies (nothing turns them), then its loaded ones, so that a
// kernel loops over each run without a per-body branch. A body whose loads start or stop turning
// it is listed (loads_changed) and placed at the start of the next step (regroup), by a swap with
// the entry at the runs' boundary.
#include "physics/world_impl.hpp"

namespace rigid::physics {

void World::Impl::set_scene_loads(int id, int b) {
  const detail::SceneLoads& scene = model().scene_loads;
  if (b < 0) {
    set_loads(id, detail::Loads{});
  } else {
    set_loads(id, scene.values[b], scene.terms[b]);
  }
}

void World::Impl::invalidate_cache(int id) {
  with_body(id, [](auto g, int i) {
    if constexpr (decltype(g)::Traits::kTurns) g.entries.plan_ok[i] = 0;
  });
}

void World::Impl::place(int id) {
  with_body(id, [&](auto g, int i) {
    auto& e = g.entries;
    const bool quiet = e.load(i).quiet();
    if (quiet == (i < e.quiet_end)) return;
    // Only this body crosses the boundary (the entry it swaps with stays in its run).
    if (detail::Entries::pushed(e.loads[i].f_W)) e.quiet_pushed += quiet ? 1 : -1;
    int j;
    if (quiet) {
      j = e.quiet_end++;
    } else {
      j = --e.quiet_end;
    }
    if (i == j) return;
    e.swap(i, j);
    data.entry[e.id[i]] = i;
    data.entry[e.id[j]] = j;
  });
}

void World::Impl::regroup() {
  for (int id : data.regroup_ids) {
    data.regroup_flag[id] = 0;
    place(id);
  }
  data.regroup_ids.clear();
}

}  // namespace rigid::physics
