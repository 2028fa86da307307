// World::step's stages (world.hpp has the pipeline), the threads that run the kernels, and the
// guard.
#include <thread>

#include "physics/world_impl.hpp"

namespace rigid::physics {

using detail::Data;
using detail::Model;
using detail::Motion;

// --- the step ---

void World::step() {
  impl_->data.contact.events.clear();
  impl_->step(false);
}

void World::step(std::int64_t n) {
  impl_->data.contact.events.clear();
  for (std::int64_t i = 0; i < n; ++i)
    impl_->step(i + 1 < n);
}

// One step; `another_follows`: the pool's workers wait for the next one polling (pool.hpp).
void World::Impl::step(bool another_follows) {
  if (!data.pending.empty()) apply_pending_impulses();
  if (!data.regroup_ids.empty()) regroup();
  const bool contacts = model().contact.enabled();
  if (contacts) contact_prepare();
  const int parts = step_parts();
  run_parts(
      parts, [](Impl& impl, detail::Share& sh) { impl.run_share(sh); }, another_follows);
  for (int k = 0; k < parts; ++k)
    data.large_rotations += shares[k].large_rotations;
  if (contacts) contact_stage();
  ++data.steps;
  guard();
}

// Momentum jumps: v += J / m, spin += the change of the spin for the angular momentum r x J (in
// P), where the body has the freedom for each; its exact-drift cache goes stale.
void World::Impl::apply_pending_impulses() {
  for (const detail::PendingImpulse& p : data.pending) {
    const int id = p.id;
    with_body(id, [&](auto g, int i) {
      Motion& m = g.motion(i);
      m.v += g.linear(i).inv_m.cwiseProduct(p.J);
      const Vec3 dL_P = m.q.conjugate() * p.L;
      if constexpr (decltype(g)::Traits::kTurns) {
        m.spin += g.rot(i).spin_rate(dL_P);
      } else {
        (void)dL_P;
      }
    });
    invalidate_cache(id);
    contact_wake(id);
    data.pending_slot[id] = -1;
  }
  data.pending.clear();
}

// The integrator's kernel over the share's slices of every group (kernels.hpp).
void World::Impl::run_share(detail::Share& sh) {
  const Model& m = model();
  Data& d = data;
  switch (m.integrator->id) {
    case IntegratorId::kNotesExplicitEuler:
    case IntegratorId::kNotesSemiImplicitEuler:
    case IntegratorId::kNotesMidpoint:
    case IntegratorId::kNotesLeapfrog:
      detail::step_notes(m, d, m.integrator->id, sh);
      break;
    case IntegratorId::kImplicitGyro:
      detail::step_implicit_gyro(m, d, sh);
      break;
    case IntegratorId::kRk4:
      detail::step_rk4(m, d, sh);
      break;
    case IntegratorId::kDlm:
      detail::step_dlm(m, d, sh);
      break;
    case IntegratorId::kExactRotor:
      detail::step_exact(m, d, false, sh);
      break;
    case IntegratorId::kExactRotor4:
      detail::step_exact(m, d, true, sh);
      break;
    case IntegratorId::kHybrid4:
      detail::step_hybrid(m, d, sh, 0);
      break;
    case IntegratorId::kHybrid4Suzuki:
      detail::step_hybrid(m, d, sh, 1);
      break;
  }
}

int World::prepare_step() {
  return impl_->prepare_step();
}

int World::Impl::prepare_step() {
  switch (model().integrator->id) {
    case IntegratorId::kExactRotor:
    case IntegratorId::kExactRotor4:
    case IntegratorId::kHybrid4:
    case IntegratorId::kHybrid4Suzuki:
      break;
    default:
      return 0;  // nothing cached
  }
  // The quiet runs as the step will see them (placing bodies moves no state).
  if (!data.regroup_ids.empty()) regroup();
  const int parts = step_parts();
  run_parts(
      parts,
      [](Impl& impl, detail::Share& sh) { detail::fill_quiet_caches(impl.model(), impl.data, sh); },
      false);
  std::int64_t made = 0;
  for (int k = 0; k < parts; ++k)
    made += shares[k].caches_made;
  return static_cast<int>(made);
}

// --- the threads ---

void World::set_threads(int n) {
  impl_->set_threads(n);
}

void World::Impl::set_threads(int n) {
  if (n < 0) throw std::invalid_argument("threads must be >= 0, got " + std::to_string(n));
  if (n == 0) n = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  threads = n;
  shares.assign(static_cast<std::size_t>(n > 1 ? max_chunks() : 1), detail::Share{});
  pool.pool = n > 1 ? std::make_unique<detail::Pool>(n) : nullptr;
}

void World::expect_step(std::int64_t within_ns) {
  const Impl& w = *impl_;
  // The same test as step(): a world stepped on the calling thread alone has no one to wake.
  if (w.pool.pool && std::min(w.threads, w.body_count() / kMinBodiesPerThread) > 1)
    w.pool.pool->expect_run(within_ns);
}
int World::threads() const {
  return impl_->threads;
}
std::span<const std::thread::native_handle_type> World::worker_threads() const {
  if (!impl_->pool.pool) return {};
  return impl_->pool.pool->worker_handles();
}

int World::Impl::step_parts() const {
  const int bodies = body_count();
  const int used = std::max(1, std::min(threads, bodies / kMinBodiesPerThread));
  // On several threads the step is cut into chunks that the threads claim (pool.hpp): small
  // enough that a thread which starts late or is preempted leaves little for the others to wait
  // for, large enough that claiming one (a compare-and-swap) costs nothing beside it.
  return used == 1 ? 1 : std::min(std::max(bodies / kBodiesPerChunk, used), max_chunks());
}

namespace {
// Slice k of `used` equal slices of [b, e), the inner ends rounded down to a multiple of `align`:
// the quiet tumbling bodies step eight at a time in blocks of eight entries (rotor_plans.hpp), and
// a block cut by a slice's end would step its bodies one at a time.
detail::Range slice(int b, int e, int k, int used, int align = 1) {
  const auto end_of = [&](int j) {
    if (j == 0) return b;
    if (j == used) return e;
    const int x = b + static_cast<int>(static_cast<long>(e - b) * j / used);
    return std::max(b, x - x % align);
  };
  return {end_of(k), end_of(k + 1)};
}
}  // namespace

void World::Impl::plan_shares(int parts) {
  for (int k = 0; k < parts; ++k) {
    detail::Share& sh = shares[k];
    sh.large_rotations = 0;
    detail::for_each_group([&](auto kind) {
      const detail::Entries& e = data.entries(kind);
      const int gi = detail::index(kind), n = e.size(), q = e.quiet_end;
      sh.all[gi] = slice(0, n, k, parts);
      sh.run[gi][0] = slice(0, q, k, parts, detail::RotorPlans::kBlock);
      sh.run[gi][1] = slice(q, n, k, parts);
    });
  }
}

void World::Impl::run_parts(int parts, void (*fn)(Impl&, detail::Share&), bool another_follows) {
  plan_shares(parts);
  if (parts == 1) {
    fn(*this, shares[0]);
    return;
  }
  struct Job {
    Impl* impl;
    void (*fn)(Impl&, detail::Share&);
  } job{this, fn};
  pool.pool->run(
      [](void* ctx, int c) {
        const Job& j = *static_cast<const Job*>(ctx);
        j.fn(*j.impl, j.impl->shares[c]);
      },
      &job, parts, another_follows);
}

// --- the guard ---

namespace {

// Finite and physically sane: every component within 1e100 (NaN fails every comparison).
constexpr double kSaneLimit = 1e100;
bool sane(const Motion& m) {
  const auto ok = [](const auto& v) { return (v.array().abs() <= kSaneLimit).all(); };
  return ok(m.x) && ok(m.v) && ok(m.spin) && ok(m.q.coeffs());
}

}  // namespace

// One slice of the bodies a step, in turn, rather than all of them every kGuardEvery steps: the
// check reads every body and writes 56 B for each to memory nothing else touches, and done for
// all at once on the calling thread it made every 64th step the slowest by far, and 1 step in 64
// is what a p99 sees (bench/notes/step-kernels.md, "The guard, a slice a step").
void World::Impl::guard() {
  const auto [begin, end] = guard_slice(static_cast<int>(data.steps % kGuardEvery));
  for (int id = begin; id < end; ++id) {
    if (data.frozen[id]) continue;
    const Motion& m = motion(id);
    if (sane(m)) {
      data.last_good[id] = detail::GuardPose(m.q, m.x);
    } else {
      freeze(id);
    }
  }
}

void World::Impl::freeze(int id) {
  Motion& m = motion(id);
  m.q = data.last_good[id].quat();
  m.x = data.last_good[id].pos();
  m.v.setZero();
  m.spin.setZero();
  with_body(id, [&](auto g, int i) {
    data.frozen_linear.push_back(g.entries.linear[i]);  // within the reserved capacity
    g.entries.linear[i] = 0;                            // no gravity, no force, no drag
  });
  const bool was_quiet = load(id).quiet();
  set_loads(id, detail::Loads{});
  loads_changed(id, was_quiet);
  if (data.pending_slot[id] >= 0) {
    data.pending[data.pending_slot[id]].J.setZero();
    data.pending[data.pending_slot[id]].L.setZero();
  }
  invalidate_cache(id);
  data.frozen[id] = 1;
  data.frozen_ids.push_back(id);  // within the reserved capacity
}

void World::Impl::thaw_all() {
  for (std::size_t k = 0; k < data.frozen_ids.size(); ++k) {
    const int id = data.frozen_ids[k];
    with_body(id, [&](auto g, int i) { g.entries.linear[i] = data.frozen_linear[k]; });
    data.frozen[id] = 0;
  }
  data.frozen_ids.clear();
  data.frozen_linear.clear();
}

std::span<const int> World::frozen_bodies() const {
  return impl_->data.frozen_ids;
}
int World::guard_phase(int id) const {
  const Impl& w = *impl_;
  w.check_id(id);
  for (int k = 0; k < kGuardEvery; ++k) {
    const auto [begin, end] = w.guard_slice(k);
    if (id >= begin && id < end) return k;
  }
  return 0;  // not reached: the slices cover every id
}
bool World::is_frozen(int id) const {
  impl_->check_id(id);
  return impl_->data.frozen[id] != 0;
}

}  // namespace rigid::physics
