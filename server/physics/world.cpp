#include "physics/world.hpp"

#include <malloc.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <initializer_list>
#include <map>
#include <sstream>
#include <thread>
#include <unordered_map>

#include "physics/hybrid_lanes.hpp"
#include "physics/inertia.hpp"
#include "physics/intern.hpp"
#include "physics/kernels.hpp"
#include "physics/model.hpp"
#include "physics/pool.hpp"
#include "physics/spec_store.hpp"

namespace rigid::physics {

using detail::AxiGroup;
using detail::DiagRot;
using detail::GenGroup;
using detail::Group;
using detail::IsoGroup;
using detail::IsoRot;
using detail::Linear;
using detail::Loads;
using detail::Model;
using detail::Motion;

namespace {

// Principal moments closer than this (relative to the largest) are treated as equal, so that a
// tensor given with round-off noise still compiles to the cheaper exact model.
constexpr double kEqualMoments = 1e-12;

// Where a body's entry is: its model and its index in that model's group, packed in 4 B (a world
// of 10^6 bodies pays for each byte a million times); World bounds the bodies to kMaxBodies.
class Slot {
 public:
  Slot() = default;
  Slot(BodyMotion m, int index) : bits_(static_cast<std::uint32_t>(index) << 2 | code(m)) {}
  BodyMotion model() const { return static_cast<BodyMotion>(bits_ & 3u); }
  int index() const { return static_cast<int>(bits_ >> 2); }
  void set_index(int index) { bits_ = (bits_ & 3u) | static_cast<std::uint32_t>(index) << 2; }

 private:
  static std::uint32_t code(BodyMotion m) { return static_cast<std::uint32_t>(m); }
  std::uint32_t bits_ = 0;
};
static_assert(static_cast<int>(BodyMotion::kTumbling) == 3, "Slot keeps a model in two bits");
static_assert(World::kMaxBodies <= (1 << 30), "Slot keeps an index in 30 bits");

std::string fmt(double x) {
  std::ostringstream os;
  os.precision(17);
  os << x;
  return os.str();
}
std::string fmt(const Vec3& v) {
  return "(" + fmt(v.x()) + ", " + fmt(v.y()) + ", " + fmt(v.z()) + ")";
}

bool finite(const Vec3& v) {
  return v.allFinite();
}

}  // namespace

namespace detail {

void build_trans_table(Model& m) {
  for (std::size_t r = 0; r < m.trans.gamma.size(); ++r) {
    const double g = m.trans.gamma[r];
    auto& row = m.trans.coef[r];
    row[kFull] = trans_coef(g, m.dt);
    row[kHalf] = trans_coef(g, 0.5 * m.dt);
    row[kStage0] = trans_coef(g, Composition::kStage[0] * m.dt);
    row[kStage1] = trans_coef(g, Composition::kStage[Composition::kStages / 2] * m.dt);
    row[kForced0] = trans_coef(g, TripleJump::kStage[0] * m.dt);
    row[kForced1] = trans_coef(g, TripleJump::kStage[1] * m.dt);
  }
}

}  // namespace detail

// Worlds of at least this many bodies give the scratch of their compilation back (compile).
constexpr int kTrimBodies = 1 << 16;

struct World::Impl {
  Vec3 g_W = Vec3::Zero();
  detail::SpecStore specs;  // the bodies' specs, validated, orientations normalised: cold
  const IntegratorInfo* integrator = nullptr;
  std::int64_t steps = 0;
  Model model;
  // Hot (what a step reads) lives in `model`; what follows is cold, read by the API, reset and
  // the guard. Per body it is kept to what cannot be derived again from the spec: a world of 10^6
  // bodies pays for every byte here a million times (bench/memory_bench.cpp).
  std::vector<Slot> slot;  // by body id (q_BP: in the groups whose P is not B, see rot_BP)
  // The spec's loads, in P, of the bodies that have any (or angular drag, which Loads flags):
  // ascending ids, and per id its entry in base_loads, where equal loads are kept once (scenes
  // give many bodies the same thruster or drag). Most bodies have none, and a dense copy cost
  // 176 B each.
  std::vector<int> base_ids;
  std::vector<std::int32_t> base_of;
  std::vector<Loads> base_loads;
  // Per base_loads entry, the shared entry of its terms in its bodies' group's pool (Group::terms;
  // 0: it has none). An entry's bodies are all of one model.
  std::vector<std::int32_t> base_terms;
  // Impulses waiting for the next step: per body the index of its entry in `pending` or -1, the
  // entries in order of arrival (capacity reserved for every body, so that apply_impulse never
  // allocates; untouched capacity is never resident).
  struct Pending {
    int id = 0;
    Vec3 J = Vec3::Zero();  // impulse (W)
    Vec3 L = Vec3::Zero();  // its angular momentum about the centre of mass (W)
  };
  std::vector<int> pending_slot;
  std::vector<Pending> pending;
  // Body ids in ascending order of name, for find_body (a hash map of the names cost ~70 B a body).
  std::vector<int> by_name;
  // The guard (see World::frozen_bodies): the pose of each body's last state that passed the check
  // (a frozen body is put back there at rest, so its velocities need no copy), and who is frozen
  // (with the index of its translational parameters before the freeze: frozen_lin).
  // Unaligned doubles: 56 B, where an aligned Quat and a Vec3 take 64.
  struct Pose {
    double q[4] = {0.0, 0.0, 0.0, 1.0};  // x, y, z, w as Quat::coeffs()
    double x[3] = {0.0, 0.0, 0.0};
    Pose() = default;
    Pose(const Quat& r, const Vec3& p) : q{r.x(), r.y(), r.z(), r.w()}, x{p.x(), p.y(), p.z()} {}
    Quat quat() const { return Quat(q[3], q[0], q[1], q[2]); }
    Vec3 pos() const { return Vec3(x[0], x[1], x[2]); }
  };
  std::vector<Pose> last_good;
  std::vector<std::uint8_t> frozen;
  std::vector<int> frozen_ids;           // capacity reserved: no allocation
  std::vector<std::int32_t> frozen_lin;  // their Group::linear.of before the freeze (capacity too)
  // Bodies whose loads may have moved them between the quiet and the loaded run of their group
  // (model.hpp), placed at the start of the next step (capacity reserved: no allocation).
  std::vector<int> regroup_ids;
  std::vector<std::uint8_t> regroup_flag;
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

  void compile(const WorldSpec& spec);
  // Body id's entry in base_loads, or -1: it has no loads of its own in the scene.
  int base_index(int id) const {
    const auto it = std::lower_bound(base_ids.begin(), base_ids.end(), id);
    return it != base_ids.end() && *it == id ? base_of[it - base_ids.begin()] : -1;
  }
  // Body id's loads back to the scene's (base_loads entry b, or none: -1), its terms shared.
  void set_base_loads(int id, int b) {
    if (b < 0) {
      set_loads(id, Loads{});
    } else {
      set_loads(id, base_loads[b], base_terms[b]);
    }
  }
  // q_BP of body id: the identity for point masses and isotropic bodies (their P is B).
  Quat rot_BP(int id) const {
    const Slot& s = slot[id];
    if (s.model() == BodyMotion::kPrecession) return model.axi.q_BP(s.index());
    if (s.model() == BodyMotion::kTumbling) return model.gen.q_BP(s.index());
    return Quat::Identity();
  }
  // A copied vector keeps its elements but not its capacity: what stepping relies on having
  // reserved (no allocation while stepping) is reserved again in a copy.
  void reserve_scratch() {
    const std::size_t n = slot.size();
    pending.reserve(n);
    frozen_ids.reserve(n);
    frozen_lin.reserve(n);
    regroup_ids.reserve(n);
    for (Group* g : {static_cast<Group*>(&model.point), static_cast<Group*>(&model.iso),
                     static_cast<Group*>(&model.axi), static_cast<Group*>(&model.gen)})
      g->reserve_terms();
  }
  // The most chunks a step is cut into (World::kChunksPerThread; what the pool can count).
  int max_chunks() const {
    return static_cast<int>(
        std::min<long>(long{kChunksPerThread} * threads, detail::Pool::kMaxChunks));
  }
  void set_threads(int n);
  void step(bool another_follows);
  int prepare_step();
  // How many chunks this world's steps are cut into (1: the calling thread alone).
  int step_parts() const;
  void plan_shares(int parts);
  // Runs fn(impl, share) for every share [0, parts), over the pool when there is more than one.
  void run_parts(int parts, void (*fn)(Impl&, detail::Share&), bool another_follows);
  void run_share(detail::Share& sh);
  // Called after anything that may change whether a body's loads leave it quiet.
  void loads_changed(int id, bool was_quiet) {
    if (load(id).quiet() != was_quiet && !regroup_flag[id]) {
      regroup_flag[id] = 1;
      regroup_ids.push_back(id);  // within the reserved capacity
    }
  }
  void regroup();
  void place(int id);
  void swap_entries(BodyMotion model, int a, int b);
  Group& group(BodyMotion m) {
    switch (m) {
      case BodyMotion::kTranslation:
        return model.point;
      case BodyMotion::kSteadySpin:
        return model.iso;
      case BodyMotion::kPrecession:
        return model.axi;
      case BodyMotion::kTumbling:
        break;
    }
    return model.gen;
  }
  const Group& group(BodyMotion m) const { return const_cast<Impl*>(this)->group(m); }
  Motion& motion(int id) { return group(slot[id].model()).motion[slot[id].index()]; }
  const Motion& motion(int id) const { return group(slot[id].model()).motion[slot[id].index()]; }
  detail::LoadsRef load(int id) const { return group(slot[id].model()).load(slot[id].index()); }
  Loads load_value(int id) const { return group(slot[id].model()).load_value(slot[id].index()); }
  void set_loads(int id, const Loads& v, std::int32_t shared_terms = 0) {
    group(slot[id].model()).set_load(slot[id].index(), v, shared_terms);
  }
  const Linear& linear(int id) const { return group(slot[id].model()).linear(slot[id].index()); }
  void invalidate_cache(int id);
  void set_state(int id, const BodyState& s);
  void apply_pending_impulses();
  // The guard's check of the bodies whose turn it is after step `steps` (World::guard_phase).
  void guard();
  // The ids [begin, end) checked at phase k (0 .. kGuardEvery - 1).
  std::pair<int, int> guard_slice(int k) const {
    const long n = static_cast<long>(slot.size());
    const int j = (k + kGuardEvery - 1) % kGuardEvery;
    return {static_cast<int>(n * j / kGuardEvery), static_cast<int>(n * (j + 1) / kGuardEvery)};
  }
  void freeze(int id);
  void thaw_all();
  Vec3 angular_momentum_P(int id) const;
  Vec3 omega_P(int id) const;
  void check_id(int id) const;
};

namespace {

// A value's doubles by their bits, for interning: equal keys, equal bits.
using Key = std::array<std::uint64_t, 8>;
Key key_of(std::initializer_list<double> xs) {
  Key k{};
  std::size_t n = 0;
  for (const double x : xs)
    k[n++] = std::bit_cast<std::uint64_t>(x);
  return k;
}
Key key_of(const Linear& l) {
  return key_of({l.g.x(), l.g.y(), l.g.z(), l.inv_m.x(), l.inv_m.y(), l.inv_m.z(), l.gamma,
                 static_cast<double>(l.drag)});
}
Key key_of(const IsoRot& r) {
  return key_of({r.inv_I, r.k, r.axis.x(), r.axis.y(), r.axis.z(), r.hinge});
}
// A Loads by its bits (LoadMath's flags and 21 doubles), for interning the spec's loads.
struct LoadsKey {
  std::array<std::uint64_t, 21> bits{};
  std::uint32_t flags = 0;
  int model = 0;  // equal loads on bodies of two models are two entries (each group's pool)
  auto operator<=>(const LoadsKey&) const = default;
};
LoadsKey key_of(const Loads& l) {
  LoadsKey k;
  k.flags = l.flags;
  std::size_t n = 0;
  for (const Vec3* v : {&l.f_W, &l.f_P, &l.tau_P, &l.tau_W})
    for (int a = 0; a < 3; ++a)
      k.bits[n++] = std::bit_cast<std::uint64_t>((*v)[a]);
  for (int a = 0; a < 9; ++a)
    k.bits[n++] = std::bit_cast<std::uint64_t>(l.fr.data()[a]);
  return k;
}
Key key_of(const Quat& q) {
  return key_of({q.w(), q.x(), q.y(), q.z()});
}
Key key_of(const DiagRot& r) {
  return key_of({r.I.x(), r.I.y(), r.I.z(), r.inv_I.x(), r.inv_I.y(), r.inv_I.z(), r.k});
}

// out: each of `values` shared, in order of first appearance; the first `skip` values (entries
// that must exist whatever the bodies) are kept but own no entry.
template <class T>
void share(const std::vector<T>& values, std::size_t skip, detail::Shared<T>& out) {
  std::vector<Key> keys;
  keys.reserve(values.size());
  for (const T& v : values)
    keys.push_back(key_of(v));
  std::vector<std::int32_t> index, first;
  detail::intern(keys, index, first);
  out.of.assign(index.begin() + static_cast<std::ptrdiff_t>(skip), index.end());
  out.values.clear();
  for (const std::int32_t f : first)
    out.values.push_back(values[f]);
}

void validate_body(const BodySpec& b, int i) {
  const auto fail = [&](const std::string& field, const std::string& what) {
    throw SpecError(i, field, "body '" + b.name + "': " + field + " " + what);
  };
  if (b.name.empty()) throw SpecError(i, "name", "body #" + std::to_string(i) + ": empty name");
  if (!b.kinematic && !(std::isfinite(b.mass) && b.mass > 0.0)) {
    fail("mass", "must be finite and > 0, got " + fmt(b.mass));
  }
  if (b.has_inertia) {
    const std::string why = inertia_problem(b.I_B);
    if (!why.empty()) fail("inertia", why);
  }
  const Eigen::Vector4d q = b.q_WB.coeffs();
  if (!q.allFinite() || q.norm() < 1e-6) {
    fail("orientation", "cannot be normalised: (w, x, y, z) = (" + fmt(b.q_WB.w()) + ", " +
                            fmt(b.q_WB.x()) + ", " + fmt(b.q_WB.y()) + ", " + fmt(b.q_WB.z()) +
                            ")");
  }
  if (!finite(b.p_WBo)) fail("position", "must be finite, got " + fmt(b.p_WBo));
  if (!finite(b.v_WBo)) fail("velocity", "must be finite, got " + fmt(b.v_WBo));
  if (!finite(b.w_WB)) fail("angular_velocity", "must be finite, got " + fmt(b.w_WB));
  if (!(std::isfinite(b.linear_drag) && b.linear_drag >= 0.0)) {
    fail("linear_drag", "must be finite and >= 0, got " + fmt(b.linear_drag));
  }
  if (!(std::isfinite(b.angular_drag) && b.angular_drag >= 0.0)) {
    fail("angular_drag", "must be finite and >= 0, got " + fmt(b.angular_drag));
  }
  const int frozen = std::count(b.freeze_rotation.begin(), b.freeze_rotation.end(), true);
  if (frozen == 1) {
    fail("freeze_rotation",
         "freezes exactly one axis: freeze 0, 2 (a hinge about the third world axis) or 3");
  }
}

}  // namespace

void World::Impl::compile(const WorldSpec& spec) {
  if (spec.bodies.size() > static_cast<std::size_t>(kMaxBodies)) {
    throw SpecError(-1, "bodies",
                    "world: at most " + std::to_string(kMaxBodies) + " bodies, got " +
                        std::to_string(spec.bodies.size()));
  }
  const int n = static_cast<int>(spec.bodies.size());
  std::uint64_t name_bytes = 0;
  for (const BodySpec& b : spec.bodies)
    name_bytes += b.name.size();
  if (name_bytes > detail::SpecStore::kMaxNameBytes) {
    throw SpecError(-1, "name",
                    "world: the bodies' names take " + std::to_string(name_bytes) +
                        " bytes, more than " + std::to_string(detail::SpecStore::kMaxNameBytes));
  }
  if (!(std::isfinite(spec.dt) && spec.dt > 0.0)) {
    throw SpecError(-1, "dt",
                    "world: dt (the physics step) must be finite and > 0, got " + fmt(spec.dt));
  }
  if (!finite(spec.g_W))
    throw SpecError(-1, "gravity", "world: gravity must be finite, got " + fmt(spec.g_W));
  if (spec.threads < 0) {
    throw SpecError(-1, "threads",
                    "world: threads must be >= 0 (0: the hardware concurrency), got " +
                        std::to_string(spec.threads));
  }
  integrator = spec.integrator.empty() ? &default_integrator() : find_integrator(spec.integrator);
  if (integrator == nullptr) {
    std::string names;
    for (const auto& i : all_integrators())
      names += (names.empty() ? "" : ", ") + std::string(i.name);
    throw SpecError(-1, "integrator",
                    "world: unknown integrator '" + spec.integrator + "' (known: " + names + ")");
  }
  // Names sorted (ties by id): the first body whose name an earlier body has is the duplicate
  // reported, after the bodies before it were validated, as a scan in scene order would.
  by_name.resize(n);
  for (int i = 0; i < n; ++i)
    by_name[i] = i;
  std::sort(by_name.begin(), by_name.end(), [&](int a, int b) {
    const int c = spec.bodies[a].name.compare(spec.bodies[b].name);
    return c < 0 || (c == 0 && a < b);
  });
  int duplicate = n;
  for (int k = 1; k < n; ++k) {
    if (spec.bodies[by_name[k]].name == spec.bodies[by_name[k - 1]].name) {
      duplicate = std::min(duplicate, by_name[k]);
    }
  }
  for (int i = 0; i < n; ++i) {
    const BodySpec& b = spec.bodies[i];
    validate_body(b, i);
    if (i == duplicate) throw SpecError(i, "name", "body '" + b.name + "': duplicate name");
  }
  for (int k = 0; k < static_cast<int>(spec.loads.size()); ++k) {
    const LoadSpec& l = spec.loads[k];
    if (l.body < 0 || l.body >= n) {
      throw SpecError(-1, "body",
                      "load #" + std::to_string(k) + ": no body #" + std::to_string(l.body), k);
    }
    if (!finite(l.force) || !finite(l.p_BoQ_B) || !finite(l.torque)) {
      throw SpecError(l.body, "force",
                      "load #" + std::to_string(k) + " on '" + spec.bodies[l.body].name +
                          "': force, point and torque must be finite",
                      k);
    }
  }

  specs = detail::SpecStore(spec.bodies);
  g_W = spec.g_W;
  model = Model{};
  model.dt = spec.dt;
  model.trans.gamma.push_back(0.0);
  slot.assign(n, Slot{});
  pending_slot.assign(n, -1);
  pending.clear();  // capacity: reserve_scratch, below
  std::unordered_map<double, int> drag_row{{0.0, 0}};
  // Per model the entries' shared parameters, interned after the loop. The translation lists
  // start with the still body's (all zero), which so becomes entry 0 (Group::linear).
  std::array<std::vector<Linear>, 4> linears;
  for (auto& l : linears)
    l.push_back(Linear{});
  std::vector<IsoRot> iso_rots;
  std::array<std::vector<DiagRot>, 2> diag_rots;  // axisymmetric, general
  std::array<std::vector<Quat>, 2> rots_BP;       // axisymmetric, general

  for (int i = 0; i < n; ++i) {
    const BodySpec& b = spec.bodies[i];
    const Quat q_WB = specs.q_WB(i);  // normalised
    const int frozen = std::count(b.freeze_rotation.begin(), b.freeze_rotation.end(), true);
    BodyMotion kind;
    PrincipalInertia pi;
    if (b.has_inertia) pi = principal_inertia(b.I_B);
    const Vec3 I = pi.moments;
    const double tol = kEqualMoments * (b.has_inertia ? I.z() : 1.0);
    IsoRot iso;
    DiagRot diag;
    if (!b.has_inertia || frozen == 3 || (b.kinematic && b.w_WB.isZero(0))) {
      kind = BodyMotion::kTranslation;
      pi = PrincipalInertia{I, Quat::Identity()};
    } else if (b.kinematic) {
      kind = BodyMotion::kSteadySpin;
      pi.q_BP = Quat::Identity();
      iso.inv_I = 0.0;
    } else if (frozen == 2) {
      // A hinge about the free world axis e: I_e = e^T R_WB I_B R_WB^T e, constant because the
      // body only turns about e. P = B; the axis in P is R_WB^T e.
      kind = BodyMotion::kSteadySpin;
      const int free_axis = !b.freeze_rotation[0] ? 0 : (!b.freeze_rotation[1] ? 1 : 2);
      const Vec3 e = Vec3::Unit(free_axis);
      const Mat3 R = q_WB.toRotationMatrix();
      const double Ie = e.dot(R * b.I_B * R.transpose() * e);
      pi.q_BP = Quat::Identity();
      iso.inv_I = 1.0 / Ie;
      iso.axis = R.transpose() * e;
      iso.hinge = 1.0;
      iso.k = b.angular_drag;
    } else if (I.z() - I.x() <= tol) {
      kind = BodyMotion::kSteadySpin;
      pi.q_BP = Quat::Identity();  // every frame is principal
      iso.inv_I = 3.0 / I.sum();
      iso.k = b.angular_drag;
    } else if (I.y() - I.x() <= tol || I.z() - I.y() <= tol) {
      kind = BodyMotion::kPrecession;
      Mat3 R = pi.q_BP.toRotationMatrix();
      Vec3 J;
      if (I.y() - I.x() <= tol) {
        J = Vec3(0.5 * (I.x() + I.y()), 0.5 * (I.x() + I.y()), I.z());
      } else {
        // Prolate: the distinct (smallest) moment goes to z by a cyclic, proper permutation.
        R = (Mat3() << R.col(1), R.col(2), R.col(0)).finished();
        J = Vec3(0.5 * (I.y() + I.z()), 0.5 * (I.y() + I.z()), I.x());
      }
      pi.q_BP = Quat(R);
      diag.I = J;
      diag.inv_I = J.cwiseInverse();
      diag.k = b.angular_drag;
    } else {
      kind = BodyMotion::kTumbling;
      diag.I = I;
      diag.inv_I = I.cwiseInverse();
      diag.k = b.angular_drag;
    }
    const Quat q_BP = pi.q_BP.normalized();  // the identity for point and isotropic bodies

    Linear lin;
    if (!b.kinematic) {
      for (int a = 0; a < 3; ++a) {
        if (b.freeze_translation[a]) continue;
        lin.inv_m[a] = 1.0 / b.mass;
        if (b.use_gravity) lin.g[a] = spec.g_W[a];
      }
      lin.gamma = b.linear_drag / b.mass;
      auto [it, added] = drag_row.emplace(lin.gamma, static_cast<int>(model.trans.gamma.size()));
      if (added) model.trans.gamma.push_back(lin.gamma);
      lin.drag = it->second;
    }

    Group& g = group(kind);
    slot[i] = Slot{kind, g.size()};
    g.id.push_back(i);
    g.motion.emplace_back();
    linears[static_cast<int>(kind)].push_back(lin);
    g.loads.emplace_back();
    switch (kind) {
      case BodyMotion::kTranslation:
        break;
      case BodyMotion::kSteadySpin:
        iso_rots.push_back(iso);
        model.iso.dq.push_back(Quat::Identity());
        model.iso.dq_ok.push_back(0);
        break;
      case BodyMotion::kPrecession:
        diag_rots[0].push_back(diag);
        model.axi.plan.emplace_back();
        model.axi.plan_ok.push_back(0);
        rots_BP[0].push_back(q_BP);
        break;
      case BodyMotion::kTumbling:
        diag_rots[1].push_back(diag);
        model.gen.plan.push_back();
        model.gen.plan_ok.push_back(0);
        rots_BP[1].push_back(q_BP);
        break;
    }
  }
  for (int k = 0; k < 4; ++k)
    share(linears[k], 1, group(static_cast<BodyMotion>(k)).linear);
  share(iso_rots, 0, model.iso.rot);
  share(diag_rots[0], 0, model.axi.rot);
  share(diag_rots[1], 0, model.gen.rot);
  {
    // Bodies that differ in drag alone share their moments, and so one rotor.
    std::map<std::array<double, 3>, std::int32_t> rotor_row;  // moments -> rotors row
    for (const DiagRot& r : model.gen.rot.values) {
      const std::array<double, 3> key{r.I.x(), r.I.y(), r.I.z()};
      const auto [it, added] =
          rotor_row.emplace(key, static_cast<std::int32_t>(model.gen.rotors.size()));
      if (added) model.gen.rotors.emplace_back(r.I);
      model.gen.rotor_of_rot.push_back(it->second);
    }
  }
  share(rots_BP[0], 0, model.axi.q_BP);
  share(rots_BP[1], 0, model.gen.q_BP);
  // The per-model lists are spent (given back below).
  linears = {};
  iso_rots = {};
  diag_rots = {};
  rots_BP = {};
  for (int i = 0; i < n; ++i) {
    const detail::SpecStore& b = specs;
    set_state(i, BodyState{b.p_WBo(i), b.q_WB(i), b.v_WBo(i), b.w_WB(i)});
  }
  model.trans.coef.resize(model.trans.gamma.size());
  detail::build_trans_table(model);
  model.lanes = detail::pick_lane_width();

  const auto has_drag = [&](int i) {
    const BodySpec& b = spec.bodies[i];
    return b.angular_drag > 0.0 && !b.kinematic && slot[i].model() != BodyMotion::kTranslation;
  };
  base_ids.clear();
  for (int i = 0; i < n; ++i) {
    if (has_drag(i)) base_ids.push_back(i);
  }
  for (const LoadSpec& l : spec.loads) {
    if (!spec.bodies[l.body].kinematic) base_ids.push_back(l.body);
  }
  std::sort(base_ids.begin(), base_ids.end());
  base_ids.erase(std::unique(base_ids.begin(), base_ids.end()), base_ids.end());
  std::vector<Loads> values(base_ids.size());
  const auto value_of = [&](int id) -> Loads& {
    return values[std::lower_bound(base_ids.begin(), base_ids.end(), id) - base_ids.begin()];
  };
  for (int i : base_ids) {
    if (has_drag(i)) value_of(i).flags |= Loads::kAngularDrag;
  }
  for (const LoadSpec& l : spec.loads) {
    const BodySpec& b = spec.bodies[l.body];
    if (b.kinematic) continue;  // a kinematic body ignores every force
    const Quat q_PB = rot_BP(l.body).conjugate();
    const Vec3 r_P = q_PB * l.p_BoQ_B;
    Loads& L = value_of(l.body);
    if (!l.force.isZero(0)) {
      L.add_force(l.frame == Frame::kBody ? Vec3(q_PB * l.force) : l.force, r_P,
                  l.frame == Frame::kBody);
    }
    if (!l.torque.isZero(0)) {
      L.add_torque(l.torque_frame == Frame::kBody ? Vec3(q_PB * l.torque) : l.torque,
                   l.torque_frame == Frame::kBody);
    }
  }
  {
    std::vector<LoadsKey> keys;
    keys.reserve(values.size());
    for (std::size_t k = 0; k < values.size(); ++k) {
      keys.push_back(key_of(values[k]));
      keys.back().model = static_cast<int>(slot[base_ids[k]].model());
    }
    std::vector<std::int32_t> first;
    detail::intern(keys, base_of, first);
    base_loads.clear();
    base_terms.clear();
    for (const std::int32_t f : first) {
      base_loads.push_back(values[f]);
      const bool terms = (values[f].flags & Loads::kTerms) != 0;
      base_terms.push_back(terms ? group(slot[base_ids[f]].model()).add_shared_terms(values[f])
                                 : 0);
    }
  }
  values = {};
  // A large world's scratch (the per-model lists, the interning's keys and indices, the
  // SpecStore's, the loads above) stays resident in glibc's heap once freed, when its dynamic
  // mmap threshold has risen. Give it back to the system before reserving what stepping may need
  // (reserve_scratch), so that those reservations take fresh pages, which stay out of memory
  // until used: 50 B a body less at 10^6 general bodies (bench/memory_bench.cpp). A small
  // world's is not worth the walk over the heap.
  if (n >= kTrimBodies) malloc_trim(0);
  reserve_scratch();
  for (std::size_t k = 0; k < base_ids.size(); ++k)
    set_base_loads(base_ids[k], base_of[k]);
  last_good.resize(n);
  for (int i = 0; i < n; ++i)
    last_good[i] = Pose(motion(i).q, motion(i).x);
  frozen.assign(n, 0);
  frozen_ids.clear();
  frozen_lin.clear();
  regroup_flag.assign(n, 0);
  regroup_ids.clear();
  for (int i = 0; i < n; ++i)
    place(i);
  set_threads(spec.threads);
}

void World::Impl::swap_entries(BodyMotion kind, int a, int b) {
  if (a == b) return;
  const auto sw = [&](auto& v) { std::swap(v[a], v[b]); };
  Group& g = group(kind);
  sw(g.id);
  sw(g.motion);
  sw(g.linear.of);
  sw(g.loads);
  switch (kind) {
    case BodyMotion::kTranslation:
      break;
    case BodyMotion::kSteadySpin:
      sw(model.iso.rot.of), model.iso.dq.swap(a, b), sw(model.iso.dq_ok);
      break;
    case BodyMotion::kPrecession:
      sw(model.axi.rot.of), sw(model.axi.plan), sw(model.axi.plan_ok), sw(model.axi.q_BP.of);
      break;
    case BodyMotion::kTumbling:
      sw(model.gen.rot.of), sw(model.gen.plan_ok);
      model.gen.plan.swap(a, b);
      sw(model.gen.q_BP.of);
      break;
  }
  slot[g.id[a]].set_index(a);
  slot[g.id[b]].set_index(b);
}

// Puts a body in the run of its group that its loads call for: a swap with the boundary entry.
void World::Impl::place(int id) {
  const Slot s = slot[id];
  Group& g = group(s.model());
  const bool quiet = g.load(s.index()).quiet();
  if (quiet == (s.index() < g.quiet_end)) return;
  // Only this body crosses the boundary (the entry it swaps with stays in its run).
  if (Group::pushed(g.loads[s.index()].f_W)) g.quiet_pushed += quiet ? 1 : -1;
  if (quiet) {
    swap_entries(s.model(), s.index(), g.quiet_end);
    ++g.quiet_end;
  } else {
    --g.quiet_end;
    swap_entries(s.model(), s.index(), g.quiet_end);
  }
}

void World::Impl::regroup() {
  for (int id : regroup_ids) {
    regroup_flag[id] = 0;
    place(id);
  }
  regroup_ids.clear();
}

void World::Impl::set_threads(int n) {
  if (n < 0) throw std::invalid_argument("threads must be >= 0, got " + std::to_string(n));
  if (n == 0) n = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  threads = n;
  shares.assign(static_cast<std::size_t>(n > 1 ? max_chunks() : 1), detail::Share{});
  pool.pool = n > 1 ? std::make_unique<detail::Pool>(n) : nullptr;
}

namespace {
// Slice k of `used` equal slices of [b, e), the inner ends rounded down to a multiple of `align`:
// the quiet general bodies step eight at a time in blocks of eight entries (rotor_plans.hpp), and
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
  const Group* gs[4] = {&model.point, &model.iso, &model.axi, &model.gen};
  for (int k = 0; k < parts; ++k) {
    detail::Share& sh = shares[k];
    sh.large_rotations = 0;
    for (int gi = 0; gi < 4; ++gi) {
      const int n = gs[gi]->size(), q = gs[gi]->quiet_end;
      sh.all[gi] = slice(0, n, k, parts);
      sh.run[gi][0] = slice(0, q, k, parts, detail::RotorPlans::kBlock);
      sh.run[gi][1] = slice(q, n, k, parts);
    }
  }
}

void World::Impl::run_share(detail::Share& sh) {
  Model& m = model;
  switch (integrator->id) {
    case IntegratorId::kNotesExplicitEuler:
    case IntegratorId::kNotesSemiImplicitEuler:
    case IntegratorId::kNotesMidpoint:
    case IntegratorId::kNotesLeapfrog:
      detail::step_notes(m, integrator->id, sh);
      break;
    case IntegratorId::kImplicitGyro:
      detail::step_implicit_gyro(m, sh);
      break;
    case IntegratorId::kRk4:
      detail::step_rk4(m, sh);
      break;
    case IntegratorId::kDlm:
      detail::step_dlm(m, sh);
      break;
    case IntegratorId::kExactRotor:
      detail::step_exact(m, false, sh);
      break;
    case IntegratorId::kExactRotor4:
      detail::step_exact(m, true, sh);
      break;
    case IntegratorId::kHybrid4:
      detail::step_hybrid(m, sh, 0);
      break;
    case IntegratorId::kHybrid4Suzuki:
      detail::step_hybrid(m, sh, 1);
      break;
  }
}

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
  const auto [begin, end] = guard_slice(static_cast<int>(steps % kGuardEvery));
  for (int id = begin; id < end; ++id) {
    if (frozen[id]) continue;
    const Motion& m = motion(id);
    if (sane(m)) {
      last_good[id] = Pose(m.q, m.x);
    } else {
      freeze(id);
    }
  }
}

void World::Impl::freeze(int id) {
  Motion& m = motion(id);
  m.q = last_good[id].quat();
  m.x = last_good[id].pos();
  m.v.setZero();
  m.spin.setZero();
  const Slot& s = slot[id];
  Group& g = group(s.model());
  frozen_lin.push_back(g.linear.of[s.index()]);  // within the reserved capacity
  g.linear.of[s.index()] = 0;                    // no gravity, no force, no drag
  const bool was_quiet = load(id).quiet();
  set_loads(id, Loads{});
  loads_changed(id, was_quiet);
  if (pending_slot[id] >= 0) {
    pending[pending_slot[id]].J.setZero();
    pending[pending_slot[id]].L.setZero();
  }
  invalidate_cache(id);
  frozen[id] = 1;
  frozen_ids.push_back(id);  // within the reserved capacity
}

void World::Impl::thaw_all() {
  for (std::size_t k = 0; k < frozen_ids.size(); ++k) {
    const int id = frozen_ids[k];
    const Slot& s = slot[id];
    group(s.model()).linear.of[s.index()] = frozen_lin[k];
    frozen[id] = 0;
  }
  frozen_ids.clear();
  frozen_lin.clear();
}

void World::Impl::check_id(int id) const {
  if (id < 0 || id >= static_cast<int>(slot.size())) {
    throw std::out_of_range("no body with id " + std::to_string(id));
  }
}

void World::Impl::invalidate_cache(int id) {
  const Slot& s = slot[id];
  switch (s.model()) {
    case BodyMotion::kSteadySpin:
      model.iso.dq_ok[s.index()] = 0;
      break;
    case BodyMotion::kPrecession:
      model.axi.plan_ok[s.index()] = 0;
      break;
    case BodyMotion::kTumbling:
      model.gen.plan_ok[s.index()] = 0;
      break;
    case BodyMotion::kTranslation:
      break;
  }
}

void World::Impl::set_state(int id, const BodyState& st) {
  const detail::SpecStore::Params& b = specs.params(id);
  Motion& m = motion(id);
  m.x = st.p_WBo;
  m.v = st.v_WBo;
  for (int a = 0; a < 3; ++a) {
    if (!allows(b.allowed_dofs, translation_dof(a)) && !b.kinematic()) m.v[a] = 0.0;
  }
  const Slot& s = slot[id];
  if (s.model() == BodyMotion::kTranslation) {
    // A point mass keeps its orientation and never turns.
    m.q = st.q_WB.normalized();
    m.spin.setZero();
  } else {
    m.q = (st.q_WB.normalized() * rot_BP(id)).normalized();
    const Vec3 w_P = m.q.conjugate() * st.w_WB;
    switch (s.model()) {
      case BodyMotion::kSteadySpin: {
        const IsoRot& r = model.iso.rot(s.index());
        m.spin = r.hinge != 0.0 ? Vec3(r.axis * r.axis.dot(w_P)) : w_P;
        break;
      }
      case BodyMotion::kPrecession:
        m.spin = model.axi.rot(s.index()).spin_of(w_P);
        break;
      case BodyMotion::kTumbling:
        m.spin = model.gen.rot(s.index()).spin_of(w_P);
        break;
      case BodyMotion::kTranslation:
        break;
    }
  }
  invalidate_cache(id);
}

void World::Impl::apply_pending_impulses() {
  for (const Pending& p : pending) {
    const int id = p.id;
    const Slot& s = slot[id];
    Group& g = group(s.model());
    Motion& m = g.motion[s.index()];
    m.v += g.linear(s.index()).inv_m.cwiseProduct(p.J);
    const Vec3 dL_P = m.q.conjugate() * p.L;
    switch (s.model()) {
      case BodyMotion::kSteadySpin:
        m.spin += model.iso.rot(s.index()).spin_rate(dL_P);
        break;
      case BodyMotion::kPrecession:
        m.spin += model.axi.rot(s.index()).spin_rate(dL_P);
        break;
      case BodyMotion::kTumbling:
        m.spin += model.gen.rot(s.index()).spin_rate(dL_P);
        break;
      case BodyMotion::kTranslation:
        break;
    }
    invalidate_cache(id);
    pending_slot[id] = -1;
  }
  pending.clear();
}

Vec3 World::Impl::angular_momentum_P(int id) const {
  const Slot& s = slot[id];
  const Motion& m = motion(id);
  switch (s.model()) {
    case BodyMotion::kTranslation:
      return Vec3::Zero();
    case BodyMotion::kSteadySpin: {
      const IsoRot& r = model.iso.rot(s.index());
      // A kinematic body has no inertia to speak of: report what its spec's tensor would give.
      if (r.inv_I == 0.0) return specs.params(id).I_B * m.spin;
      return m.spin / r.inv_I;
    }
    case BodyMotion::kPrecession:
    case BodyMotion::kTumbling:
      return m.spin;  // the angular momentum itself
  }
  return Vec3::Zero();
}

Vec3 World::Impl::omega_P(int id) const {
  const Slot& s = slot[id];
  const Motion& m = motion(id);
  switch (s.model()) {
    case BodyMotion::kTranslation:
      return Vec3::Zero();
    case BodyMotion::kSteadySpin:
      return model.iso.rot(s.index()).omega(m.spin);
    case BodyMotion::kPrecession:
      return model.axi.rot(s.index()).omega(m.spin);
    case BodyMotion::kTumbling:
      return model.gen.rot(s.index()).omega(m.spin);
  }
  return Vec3::Zero();
}

World::World(const WorldSpec& spec) : impl_(std::make_unique<Impl>()) {
  impl_->compile(spec);
}
World::~World() = default;
World::World(World&&) noexcept = default;
World& World::operator=(World&&) noexcept = default;
World::World(const World& o) : impl_(std::make_unique<Impl>(*o.impl_)) {
  impl_->reserve_scratch();
}
World& World::operator=(const World& o) {
  if (this != &o) {
    impl_ = std::make_unique<Impl>(*o.impl_);
    impl_->reserve_scratch();
  }
  return *this;
}

void World::step() {
  impl_->step(false);
}

void World::step(std::int64_t n) {
  for (std::int64_t i = 0; i < n; ++i)
    impl_->step(i + 1 < n);
}

int World::Impl::step_parts() const {
  const int bodies = static_cast<int>(slot.size());
  const int used = std::max(1, std::min(threads, bodies / kMinBodiesPerThread));
  // On several threads the step is cut into chunks that the threads claim (pool.hpp): small
  // enough that a thread which starts late or is preempted leaves little for the others to wait
  // for, large enough that claiming one (a compare-and-swap) costs nothing beside it.
  return used == 1 ? 1 : std::min(std::max(bodies / kBodiesPerChunk, used), max_chunks());
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

// One step; `another_follows`: the pool's workers wait for the next one polling (pool.hpp).
void World::Impl::step(bool another_follows) {
  Impl& w = *this;
  if (!w.pending.empty()) w.apply_pending_impulses();
  if (!w.regroup_ids.empty()) w.regroup();
  const int parts = w.step_parts();
  w.run_parts(
      parts, [](Impl& impl, detail::Share& sh) { impl.run_share(sh); }, another_follows);
  for (int k = 0; k < parts; ++k)
    w.model.large_rotations += w.shares[k].large_rotations;
  ++w.steps;
  w.guard();
}

int World::prepare_step() {
  return impl_->prepare_step();
}

int World::Impl::prepare_step() {
  switch (integrator->id) {
    case IntegratorId::kExactRotor:
    case IntegratorId::kExactRotor4:
    case IntegratorId::kHybrid4:
    case IntegratorId::kHybrid4Suzuki:
      break;
    default:
      return 0;  // nothing cached
  }
  // The quiet runs as the step will see them (placing bodies moves no state).
  if (!regroup_ids.empty()) regroup();
  const int parts = step_parts();
  run_parts(
      parts, [](Impl& impl, detail::Share& sh) { detail::fill_quiet_caches(impl.model, sh); },
      false);
  std::int64_t made = 0;
  for (int k = 0; k < parts; ++k)
    made += shares[k].caches_made;
  return static_cast<int>(made);
}

void World::set_threads(int n) {
  impl_->set_threads(n);
}
void World::expect_step(std::int64_t within_ns) {
  const Impl& w = *impl_;
  const int bodies = static_cast<int>(w.slot.size());
  // The same test as step(): a world stepped on the calling thread alone has no one to wake.
  if (w.pool.pool && std::min(w.threads, bodies / kMinBodiesPerThread) > 1)
    w.pool.pool->expect_run(within_ns);
}
int World::threads() const {
  return impl_->threads;
}
std::span<const std::thread::native_handle_type> World::worker_threads() const {
  if (!impl_->pool.pool) return {};
  return impl_->pool.pool->worker_handles();
}

double World::dt() const {
  return impl_->model.dt;
}
std::int64_t World::large_rotation_steps() const {
  return impl_->model.large_rotations;
}
double World::time() const {
  return static_cast<double>(impl_->steps) * impl_->model.dt;
}
std::int64_t World::step_count() const {
  return impl_->steps;
}
const IntegratorInfo& World::integrator() const {
  return *impl_->integrator;
}
int World::body_count() const {
  return static_cast<int>(impl_->slot.size());
}

int World::find_body(std::string_view name) const {
  const Impl& w = *impl_;
  const auto it =
      std::lower_bound(w.by_name.begin(), w.by_name.end(), name,
                       [&](int id, std::string_view n) { return w.specs.name(id) < n; });
  return it != w.by_name.end() && w.specs.name(*it) == name ? *it : -1;
}

BodySpec World::body_spec(int id) const {
  impl_->check_id(id);
  return impl_->specs.get(id);
}
std::string_view World::body_name(int id) const {
  impl_->check_id(id);
  return impl_->specs.name(id);
}
BodyMotion World::body_motion(int id) const {
  impl_->check_id(id);
  return impl_->slot[id].model();
}
MotionType World::motion_type(int id) const {
  impl_->check_id(id);
  return impl_->specs.params(id).motion_type;
}
AllowedDofs World::allowed_dofs(int id) const {
  impl_->check_id(id);
  return impl_->specs.params(id).allowed_dofs;
}
Vec3 World::principal_moments(int id) const {
  impl_->check_id(id);
  // Not stored: the model's own moments, or the spec's for a kinematic body (no inertia in use).
  const Impl& w = *impl_;
  const Slot& s = w.slot[id];
  switch (s.model()) {
    case BodyMotion::kTranslation:
      break;
    case BodyMotion::kSteadySpin: {
      const double inv_I = w.model.iso.rot(s.index()).inv_I;
      return inv_I > 0 ? Vec3::Constant(1.0 / inv_I)
                       : principal_inertia(w.specs.params(id).I_B).moments;
    }
    case BodyMotion::kPrecession:
      return w.model.axi.rot(s.index()).I;
    case BodyMotion::kTumbling:
      return w.model.gen.rot(s.index()).I;
  }
  return Vec3::Zero();
}
Quat World::q_BP(int id) const {
  impl_->check_id(id);
  return impl_->rot_BP(id);
}

BodyState World::state(int id) const {
  impl_->check_id(id);
  const Motion& m = impl_->motion(id);
  BodyState s;
  s.p_WBo = m.x;
  s.v_WBo = m.v;
  if (impl_->slot[id].model() == BodyMotion::kTranslation) {
    s.q_WB = m.q;
    s.w_WB.setZero();
  } else {
    s.q_WB = m.q * impl_->rot_BP(id).conjugate();
    s.w_WB = rotate(m.q, impl_->omega_P(id));
  }
  return s;
}

namespace {

// Bodies [begin, end) of the models in write order (point masses, isotropic, axisymmetric,
// general: each model's entries in turn) into rows, at their body ids.
struct StateWriter {
  const detail::Model& model;
  StateRows rows;

  void put(int id, const Motion& m, const Quat& q_WB, const Vec3& w_WB) const {
    const auto k = static_cast<std::size_t>(id);
    double* p = rows.p_WBo + 3 * k;
    double* q = rows.q_WB_wxyz + 4 * k;
    double* v = rows.v_WBo + 3 * k;
    double* o = rows.w_WB + 3 * k;
    p[0] = m.x.x(), p[1] = m.x.y(), p[2] = m.x.z();
    q[0] = q_WB.w(), q[1] = q_WB.x(), q[2] = q_WB.y(), q[3] = q_WB.z();
    v[0] = m.v.x(), v[1] = m.v.y(), v[2] = m.v.z();
    o[0] = w_WB.x(), o[1] = w_WB.y(), o[2] = w_WB.z();
  }

  // The same expressions as World::state(id), per model, so that both give the same bits.
  void write(int begin, int end) const {
    int base = 0;
    const auto span = [&](int size, auto&& one) {
      const int lo = std::max(begin - base, 0), hi = std::min(end - base, size);
      for (int k = lo; k < hi; ++k)
        one(k);
      base += size;
    };
    const detail::PointGroup& point = model.point;
    span(point.size(), [&](int k) {
      const Motion& m = point.motion[k];
      put(point.id[k], m, m.q, Vec3::Zero());
    });
    const IsoGroup& iso = model.iso;
    span(iso.size(), [&](int k) {
      const Motion& m = iso.motion[k];
      put(iso.id[k], m, m.q * Quat::Identity().conjugate(), rotate(m.q, iso.rot(k).omega(m.spin)));
    });
    const auto rotated = [&](const auto& g) {
      span(g.size(), [&](int k) {
        const Motion& m = g.motion[k];
        put(g.id[k], m, m.q * g.q_BP(k).conjugate(), rotate(m.q, g.rot(k).omega(m.spin)));
      });
    };
    rotated(model.axi);
    rotated(model.gen);
  }
};

}  // namespace

void World::write_states(const StateRows& rows) const {
  const Impl& w = *impl_;
  const StateWriter writer{w.model, rows};
  const int bodies = static_cast<int>(w.slot.size());
  // A large world's states are written on the step's threads too, in chunks they claim: what
  // each body's rows hold does not depend on which thread wrote them. (rigidd writes every state
  // it publishes on its loop thread: what that costs at 10^5 bodies is in bench/notes/
  // loop-latency.md, "Writing the state".)
  const int chunks = std::min(bodies / kBodiesPerWriteChunk, detail::Pool::kMaxChunks);
  if (!w.pool.pool || w.threads < 2 || chunks < 2) {
    writer.write(0, bodies);
    return;
  }
  struct Job {
    const StateWriter& writer;
    int bodies, chunks;
  } job{writer, bodies, chunks};
  w.pool.pool->run(
      [](void* ctx, int c) {
        const Job& j = *static_cast<const Job*>(ctx);
        const auto at = [&](int k) {
          return static_cast<int>(std::int64_t{j.bodies} * k / j.chunks);
        };
        j.writer.write(at(c), at(c + 1));
      },
      &job, chunks);
}

void World::set_state(int id, const BodyState& s) {
  impl_->check_id(id);
  if (!s.p_WBo.allFinite() || !s.v_WBo.allFinite() || !s.w_WB.allFinite() ||
      !s.q_WB.coeffs().allFinite() || s.q_WB.norm() < 1e-6) {
    throw std::invalid_argument("set_state: body '" + std::string(impl_->specs.name(id)) +
                                "': the state must be finite, with a non-zero quaternion");
  }
  impl_->set_state(id, s);
}

void World::reset() {
  Impl& w = *impl_;
  w.steps = 0;
  w.model.large_rotations = 0;
  w.thaw_all();
  for (int i = 0; i < body_count(); ++i) {
    const detail::SpecStore& b = w.specs;
    w.set_state(i, BodyState{b.p_WBo(i), b.q_WB(i), b.v_WBo(i), b.w_WB(i)});
  }
  for (const Impl::Pending& p : w.pending)
    w.pending_slot[p.id] = -1;
  w.pending.clear();
  clear_applied();
  for (int i = 0; i < body_count(); ++i)
    w.last_good[i] = Impl::Pose(w.motion(i).q, w.motion(i).x);
}

void World::clear_applied() {
  Impl& w = *impl_;
  std::size_t k = 0;  // walks base_ids, ascending like i
  for (int i = 0; i < body_count(); ++i) {
    const bool has_base = k < w.base_ids.size() && w.base_ids[k] == i;
    const int b = has_base ? w.base_of[k++] : -1;
    const bool was_quiet = w.load(i).quiet();
    w.set_base_loads(i, w.frozen[i] ? -1 : b);
    w.loads_changed(i, was_quiet);
  }
}

void World::clear_applied(int id) {
  impl_->check_id(id);
  const bool was_quiet = impl_->load(id).quiet();
  impl_->set_base_loads(id, impl_->frozen[id] ? -1 : impl_->base_index(id));
  impl_->loads_changed(id, was_quiet);
}

std::span<const int> World::frozen_bodies() const {
  return impl_->frozen_ids;
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
  return impl_->frozen[id] != 0;
}

void World::add_force(int id, const Vec3& f, const Vec3& p_BoQ_B, Frame frame) {
  Impl& w = *impl_;
  w.check_id(id);
  if (w.specs.params(id).kinematic() || w.frozen[id]) return;
  const Quat q_PB = w.rot_BP(id).conjugate();
  const bool body = frame == Frame::kBody;
  const bool was_quiet = w.load(id).quiet();
  Loads v = w.load_value(id);
  v.add_force(body ? Vec3(q_PB * f) : f, q_PB * p_BoQ_B, body);
  w.set_loads(id, v);
  w.loads_changed(id, was_quiet);
}

void World::add_torque(int id, const Vec3& tau, Frame frame) {
  Impl& w = *impl_;
  w.check_id(id);
  if (w.specs.params(id).kinematic() || w.frozen[id]) return;
  const bool body = frame == Frame::kBody;
  const bool was_quiet = w.load(id).quiet();
  Loads v = w.load_value(id);
  v.add_torque(body ? Vec3(w.rot_BP(id).conjugate() * tau) : tau, body);
  w.set_loads(id, v);
  w.loads_changed(id, was_quiet);
}

void World::apply_impulse(int id, const Vec3& J, const Vec3& p_BoQ_B, Frame frame) {
  Impl& w = *impl_;
  w.check_id(id);
  if (w.specs.params(id).kinematic() || w.frozen[id]) return;
  const BodyState s = state(id);
  const Vec3 J_W = frame == Frame::kBody ? Vec3(s.q_WB * J) : J;
  const Vec3 r_W = s.q_WB * p_BoQ_B;
  if (w.pending_slot[id] < 0) {
    w.pending_slot[id] = static_cast<int>(w.pending.size());
    w.pending.push_back(Impl::Pending{id, Vec3::Zero(), Vec3::Zero()});  // within the capacity
  }
  Impl::Pending& p = w.pending[w.pending_slot[id]];
  p.J += J_W;
  p.L += r_W.cross(J_W);
}

double World::kinetic_energy(int id) const {
  impl_->check_id(id);
  const Motion& m = impl_->motion(id);
  const double mass = impl_->specs.params(id).mass;
  return 0.5 * mass * m.v.squaredNorm() +
         0.5 * impl_->omega_P(id).dot(impl_->angular_momentum_P(id));
}

double World::total_energy() const {
  double e = 0.0;
  for (int i = 0; i < body_count(); ++i) {
    e += kinetic_energy(i);
    const Linear& lin = impl_->linear(i);
    e -= impl_->specs.params(i).mass * lin.g.dot(impl_->motion(i).x);
  }
  return e;
}

Vec3 World::angular_momentum_W(int id) const {
  impl_->check_id(id);
  return impl_->motion(id).q * impl_->angular_momentum_P(id);
}

}  // namespace rigid::physics
