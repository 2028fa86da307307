// Building a World from its WorldSpec (World::Impl::build), in named stages:
//   validate     the spec as a whole, each body and each load: SpecError naming the field and
//   value; classify     each body from its stored parameters: its motion group (body_motion.hpp)
//   and the
//                parameters of its translation, rotation and principal frame; its entry in its
//                group (Data);
//   intern       equal parameters kept once: the groups' tables (Model) and each entry's rows in
//                them (Data); the translation coefficients per drag rate;
//   build loads  the scene's loads in P, once per distinct value, and their terms in the groups'
//                pools;
//   place        the initial states and guard poses, every buffer stepping may need reserved, each
//                body's scene loads, each body in the run of its group its loads call for, the
//                threads.
// Every stage but the last writes the Model; from then on it is constant (world_impl.hpp).
#include <malloc.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <initializer_list>
#include <map>
#include <sstream>
#include <thread>
#include <tuple>
#include <unordered_map>

#include "physics/hybrid_lanes.hpp"
#include "physics/inertia.hpp"
#include "physics/intern.hpp"
#include "physics/world_impl.hpp"

namespace rigid::physics {

using detail::Data;
using detail::DiagRot;
using detail::GroupTag;
using detail::Linear;
using detail::Loads;
using detail::Model;
using detail::SpecStore;
using detail::SpinRot;

namespace {

// Principal moments closer than this (relative to the largest) are treated as equal, so that a
// tensor given with round-off noise still compiles to the cheaper exact motion.
constexpr double kEqualMoments = 1e-12;
// Worlds of at least this many bodies give the scratch of their build back (place).
constexpr int kTrimBodies = 1 << 16;

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

// --- validate ---

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

// The world's own fields, then the bodies in scene order (a duplicate name reported at the first
// body whose name an earlier body has, after the bodies before it), then the loads. Returns the
// integrator and fills `by_name` (Model::by_name), which the duplicate check sorts anyway.
const IntegratorInfo* validate(const WorldSpec& spec, std::vector<int>& by_name) {
  if (spec.bodies.size() > static_cast<std::size_t>(World::kMaxBodies)) {
    throw SpecError(-1, "bodies",
                    "world: at most " + std::to_string(World::kMaxBodies) + " bodies, got " +
                        std::to_string(spec.bodies.size()));
  }
  const int n = static_cast<int>(spec.bodies.size());
  std::uint64_t name_bytes = 0;
  for (const BodySpec& b : spec.bodies)
    name_bytes += b.name.size();
  if (name_bytes > SpecStore::kMaxNameBytes) {
    throw SpecError(-1, "name",
                    "world: the bodies' names take " + std::to_string(name_bytes) +
                        " bytes, more than " + std::to_string(SpecStore::kMaxNameBytes));
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
  const IntegratorInfo* integrator =
      spec.integrator.empty() ? &default_integrator() : find_integrator(spec.integrator);
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
  return integrator;
}

// --- classify ---

// A group's entries' parameters in entry order, before they are interned. The translation list
// starts with a still body's (all zero), which so becomes row 0 (GroupParams::linear).
template <BodyMotion K>
struct ParamLists {
  using Traits = detail::GroupTraits<K>;
  std::vector<Linear> linear{Linear{}};
  std::conditional_t<Traits::kTurns, std::vector<typename Traits::Rot>, detail::None> rot;
  std::conditional_t<Traits::kPrincipalFrame, std::vector<Quat>, detail::None> q_BP;
};
using AllParamLists =
    std::tuple<ParamLists<BodyMotion::kTranslation>, ParamLists<BodyMotion::kSteadySpin>,
               ParamLists<BodyMotion::kPrecession>, ParamLists<BodyMotion::kTumbling>>;
template <BodyMotion K>
ParamLists<K>& lists_of(AllParamLists& lists, GroupTag<K>) {
  return std::get<detail::index(K)>(lists);
}

// Each body's motion group (body_motion.hpp says which bodies each holds) and parameters, from its
// stored spec; its entry appended to its group, its parameters to the group's lists, the drag
// rates to the model's translation table (row 0: no drag).
void classify(Model& model, Data& data, AllParamLists& lists) {
  const SpecStore& specs = model.specs;
  const int n = specs.size();
  model.trans.gamma.push_back(0.0);
  std::unordered_map<double, int> drag_row{{0.0, 0}};
  model.motion.resize(n);
  data.entry.resize(n);
  for (int i = 0; i < n; ++i) {
    const SpecStore::Params& b = specs.params(i);
    const Quat q_WB = specs.q_WB(i);  // normalised
    const int locked = locked_rotations(b.allowed_dofs);
    BodyMotion kind;
    PrincipalInertia pi;
    if (b.has_inertia) pi = principal_inertia(b.I_B);
    const Vec3 I = pi.moments;
    const double tol = kEqualMoments * (b.has_inertia ? I.z() : 1.0);
    SpinRot spin;
    DiagRot diag;
    if (!b.has_inertia || locked == 3 || (b.kinematic() && specs.w_WB(i).isZero(0))) {
      kind = BodyMotion::kTranslation;
      pi = PrincipalInertia{I, Quat::Identity()};
    } else if (b.kinematic()) {
      kind = BodyMotion::kSteadySpin;
      pi.q_BP = Quat::Identity();
      spin.inv_I = 0.0;
    } else if (locked == 2) {
      // A hinge about the free world axis e: I_e = e^T R_WB I_B R_WB^T e, constant because the
      // body only turns about e. P = B; the axis in P is R_WB^T e.
      kind = BodyMotion::kSteadySpin;
      const int free_axis = allows(b.allowed_dofs, rotation_dof(0))   ? 0
                            : allows(b.allowed_dofs, rotation_dof(1)) ? 1
                                                                      : 2;
      const Vec3 e = Vec3::Unit(free_axis);
      const Mat3 R = q_WB.toRotationMatrix();
      const double Ie = e.dot(R * b.I_B * R.transpose() * e);
      pi.q_BP = Quat::Identity();
      spin.inv_I = 1.0 / Ie;
      spin.axis = R.transpose() * e;
      spin.hinge = 1.0;
      spin.k = b.angular_drag;
    } else if (I.z() - I.x() <= tol) {
      kind = BodyMotion::kSteadySpin;
      pi.q_BP = Quat::Identity();  // every frame is principal
      spin.inv_I = 3.0 / I.sum();
      spin.k = b.angular_drag;
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
    const Quat q_BP = pi.q_BP.normalized();  // the identity where P is B

    Linear lin;
    if (!b.kinematic()) {
      for (int a = 0; a < 3; ++a) {
        if (!allows(b.allowed_dofs, translation_dof(a))) continue;
        lin.inv_m[a] = 1.0 / b.mass;
        if (b.use_gravity) lin.g[a] = model.g_W[a];
      }
      lin.gamma = b.linear_drag / b.mass;
      auto [it, added] = drag_row.emplace(lin.gamma, static_cast<int>(model.trans.gamma.size()));
      if (added) model.trans.gamma.push_back(lin.gamma);
      lin.drag = it->second;
    }

    model.motion[i] = kind;
    detail::visit(kind, [&](auto k) {
      using Traits = detail::GroupTraits<decltype(k)::value>;
      auto& e = data.entries(k);
      auto& l = lists_of(lists, k);
      data.entry[i] = e.size();
      e.id.push_back(i);
      e.motion.emplace_back();
      e.loads.emplace_back();
      l.linear.push_back(lin);
      if constexpr (decltype(k)::value == BodyMotion::kSteadySpin) {
        l.rot.push_back(spin);
        e.plan.push_back(Quat::Identity());
      } else if constexpr (Traits::kTurns) {
        l.rot.push_back(diag);
        e.plan.push_back();
      }
      if constexpr (Traits::kTurns) e.plan_ok.push_back(0);
      if constexpr (Traits::kPrincipalFrame) l.q_BP.push_back(q_BP);
    });
  }
}

// --- intern ---

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
Key key_of(const SpinRot& r) {
  return key_of({r.inv_I, r.k, r.axis.x(), r.axis.y(), r.axis.z(), r.hinge});
}
Key key_of(const Quat& q) {
  return key_of({q.w(), q.x(), q.y(), q.z()});
}
Key key_of(const DiagRot& r) {
  return key_of({r.I.x(), r.I.y(), r.I.z(), r.inv_I.x(), r.inv_I.y(), r.inv_I.z(), r.k});
}

// `table`: each of `values` once, in order of first appearance; `rows`: each value's row of it,
// but for the first `skip` values (rows that must exist whatever the bodies), which own no entry.
template <class T>
void share(const std::vector<T>& values, std::size_t skip, std::vector<T>& table,
           std::vector<std::int32_t>& rows) {
  std::vector<Key> keys;
  keys.reserve(values.size());
  for (const T& v : values)
    keys.push_back(key_of(v));
  std::vector<std::int32_t> index, first;
  detail::intern(keys, index, first);
  rows.assign(index.begin() + static_cast<std::ptrdiff_t>(skip), index.end());
  table.clear();
  for (const std::int32_t f : first)
    table.push_back(values[f]);
}

// Each group's lists interned into its tables and its entries' rows; the tumbling group's rotor
// constants once per distinct moments (bodies that differ in drag alone share one rotor).
void intern(AllParamLists& lists, Model& model, Data& data) {
  detail::for_each_group([&](auto k) {
    using Traits = detail::GroupTraits<decltype(k)::value>;
    auto& l = lists_of(lists, k);
    auto& p = model.params(k);
    auto& e = data.entries(k);
    share(l.linear, 1, p.linear, e.linear);
    if constexpr (Traits::kTurns) share(l.rot, 0, p.rot, e.rot);
    if constexpr (Traits::kPrincipalFrame) share(l.q_BP, 0, p.q_BP, e.q_BP);
    if constexpr (decltype(k)::value == BodyMotion::kTumbling) {
      std::map<std::array<double, 3>, std::int32_t> rotor_row;  // moments -> rotors row
      for (const DiagRot& r : p.rot) {
        const std::array<double, 3> key{r.I.x(), r.I.y(), r.I.z()};
        const auto [it, added] =
            rotor_row.emplace(key, static_cast<std::int32_t>(p.rotors.values.size()));
        if (added) p.rotors.values.emplace_back(r.I);
        p.rotors.of_rot.push_back(it->second);
      }
    }
    l = {};  // spent: given back before the loads are built
  });
  model.trans.coef.resize(model.trans.gamma.size());
  detail::build_trans_table(model);
  model.lanes = detail::pick_lane_width();
}

// --- build loads ---

// A Loads by its bits (LoadMath's flags and 21 doubles), for interning the spec's loads.
struct LoadsKey {
  std::array<std::uint64_t, 21> bits{};
  std::uint32_t flags = 0;
  int group = 0;  // equal loads on bodies of two groups are two entries (each group's pool)
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

int SceneLoads::index(int id) const {
  const auto it = std::lower_bound(ids.begin(), ids.end(), id);
  return it != ids.end() && *it == id ? of[it - ids.begin()] : -1;
}

}  // namespace detail

World::World(const WorldSpec& spec) : impl_(std::make_unique<Impl>()) {
  impl_->build(spec);
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

void World::Impl::reserve_scratch() {
  const std::size_t n = data.entry.size();
  data.pending.reserve(n);
  data.frozen_ids.reserve(n);
  data.frozen_linear.reserve(n);
  data.regroup_ids.reserve(n);
  detail::for_each_group([&](auto k) { data.entries(k).reserve_terms(); });
  reserve_contacts();
}

// The scene's loads (Model::scene_loads): of the bodies with angular drag or loads of their own,
// kinematic bodies aside (they ignore every force), in P, equal ones kept once per group; the
// terms of each in its group's pool, shared by its bodies (Entries::add_shared_terms).
void World::Impl::build_loads(const WorldSpec& spec, Model& model) {
  const SpecStore& specs = model.specs;
  detail::SceneLoads& out = model.scene_loads;
  const int n = specs.size();
  const auto has_drag = [&](int i) {
    const SpecStore::Params& b = specs.params(i);
    return b.angular_drag > 0.0 && !b.kinematic() && model.motion[i] != BodyMotion::kTranslation;
  };
  out.ids.clear();
  for (int i = 0; i < n; ++i) {
    if (has_drag(i)) out.ids.push_back(i);
  }
  for (const LoadSpec& l : spec.loads) {
    if (!specs.params(l.body).kinematic()) out.ids.push_back(l.body);
  }
  std::sort(out.ids.begin(), out.ids.end());
  out.ids.erase(std::unique(out.ids.begin(), out.ids.end()), out.ids.end());
  std::vector<Loads> values(out.ids.size());
  const auto value_of = [&](int id) -> Loads& {
    return values[std::lower_bound(out.ids.begin(), out.ids.end(), id) - out.ids.begin()];
  };
  for (int i : out.ids) {
    if (has_drag(i)) value_of(i).flags |= Loads::kAngularDrag;
  }
  for (const LoadSpec& l : spec.loads) {
    if (specs.params(l.body).kinematic()) continue;  // a kinematic body ignores every force
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
  std::vector<LoadsKey> keys;
  keys.reserve(values.size());
  for (std::size_t k = 0; k < values.size(); ++k) {
    keys.push_back(key_of(values[k]));
    keys.back().group = detail::index(model.motion[out.ids[k]]);
  }
  std::vector<std::int32_t> first;
  detail::intern(keys, out.of, first);
  keys = {};
  out.values.clear();
  out.terms.clear();
  for (const std::int32_t f : first) {
    out.values.push_back(values[f]);
    const bool terms = (values[f].flags & Loads::kTerms) != 0;
    out.terms.push_back(!terms ? 0 : with_body(out.ids[f], [&](auto g, int) {
      return g.entries.add_shared_terms(values[f]);
    }));
  }
}

void World::Impl::build(const WorldSpec& spec) {
  // The model under construction; model_ptr (const) shares it, so that what reads the model
  // while it is built (rot_BP, with_body) reads this one.
  const auto m = std::make_shared<Model>();
  model_ptr = m;
  Model& model = *m;
  data = Data{};

  model.integrator = validate(spec, model.by_name);
  model.specs = SpecStore(spec.bodies);
  model.dt = spec.dt;
  model.g_W = spec.g_W;
  {
    AllParamLists lists;
    classify(model, data, lists);
    intern(lists, model, data);
  }
  build_loads(spec, model);
  build_contacts(spec, model);
  place_bodies(spec.threads);
  reset_contacts();
}

void World::Impl::place_bodies(int threads_wanted) {
  const Model& model = this->model();
  // A large world's scratch (the parameter lists, the interning's keys and indices, the
  // SpecStore's, the loads') stays resident in glibc's heap once freed, when its dynamic mmap
  // threshold has risen. Give it back to the system before reserving what stepping may need
  // (reserve_scratch), so that those reservations take fresh pages, which stay out of memory
  // until used: 50 B a body less at 10^6 general bodies (bench/physics/memory_bench.cpp). A small
  // world's is not worth the walk over the heap.
  const int n = model.body_count();
  if (n >= kTrimBodies) malloc_trim(0);
  data.pending_slot.assign(n, -1);
  reserve_scratch();
  for (int i = 0; i < n; ++i) {
    const SpecStore& b = model.specs;
    set_state(i, BodyState{b.p_WBo(i), b.q_WB(i), b.v_WBo(i), b.w_WB(i)});
  }
  const detail::SceneLoads& scene = model.scene_loads;
  for (std::size_t k = 0; k < scene.ids.size(); ++k)
    set_scene_loads(scene.ids[k], scene.of[k]);
  data.last_good.resize(n);
  for (int i = 0; i < n; ++i)
    data.last_good[i] = detail::GuardPose(motion(i).q, motion(i).x);
  data.frozen.assign(n, 0);
  data.regroup_flag.assign(n, 0);
  for (int i = 0; i < n; ++i)
    place(i);
  set_threads(threads_wanted);
}

}  // namespace rigid::physics
