// The motion groups: a compiled world keeps its bodies in four groups, one per kind of motion its
// step computes (body_motion.hpp: BodyMotion), each in contiguous arrays, so that an integrator's
// loop over a group has no per-body branch on the kind of body (Box2D v3's solver sets).
//
// A group is one template, Group<K>, with what only some kinds have chosen by GroupTraits<K>
// (`if constexpr` where code differs), and it is split as the world is (MuJoCo's mjModel/mjData):
//   GroupParams<K>  (in the Model, constant once the world is built): the parameter tables the
//                   bodies share (a world of 10^6 bodies usually has a handful of kinds);
//   GroupEntries<K> (in the Data): per entry its body id, motion, rows of those tables, loads and
//                   exact-drift cache, kept in two runs (quiet, then loaded) that bodies move
//                   between;
//   Group<K>        a view pairing the two, which the kernels and the World step through:
//                   g.rot(i) is entry i's row of the rotation table, g.motion(i) its motion.
// visit(kind, f) calls f with the kind as a compile-time tag; for_each_group(f) calls it for every
// kind in order. Nothing else switches over the kind.
//
// Every body's state is kept about its centre of mass in its principal frame P:
//   Motion::q = q_WP, Motion::x = p_WBo, Motion::v = v_WBo (in W), and Motion::spin, expressed in
//   P: the angular velocity w_P for the steady-spin group, the angular momentum h_P = I w_P for
//   precession and tumbling (none for translation: zero). Momentum is what the splittings and the
//   exact rotor evolve and what torque changes directly; keeping it as the state spares every step
//   a round trip h = I w, w = h / I, whose rounding is a fixed bias per axis (I * (1/I) != 1) that
//   a long run accumulates. The rotational parameters convert (omega, spin_of) where a scheme needs
//   w.
#pragma once

#include <cstdint>
#include <cstring>
#include <type_traits>
#include <vector>

#include "physics/body_motion.hpp"
#include "physics/free_rotor.hpp"
#include "physics/iso_lanes.hpp"
#include "physics/loads.hpp"
#include "physics/rotor_plans.hpp"

namespace rigid::physics::detail {

struct Motion {
  Quat q = Quat::Identity();
  Vec3 x = Vec3::Zero();
  Vec3 v = Vec3::Zero();
  Vec3 spin = Vec3::Zero();
};

// Translation parameters (every group).
struct Linear {
  Vec3 g = Vec3::Zero();      // gravity, zero on locked axes and when the body ignores it
  Vec3 inv_m = Vec3::Zero();  // 1/m, zero on locked axes and for kinematic bodies
  double gamma = 0.0;         // linear drag rate c / m (1/s)
  int drag = 0;               // row of TransTable for this gamma (row 0: gamma = 0)

  Vec3 accel(const Vec3& f_W) const { return g + inv_m.cwiseProduct(f_W); }
};

// The steady-spin group's rotational parameters. An isotropic body needs no gyroscopic term; a
// hinge's axis (the one free world axis) is fixed in P too, and the constraint absorbs every other
// torque; a kinematic body has inv_I = 0.
struct SpinRot {
  double inv_I = 0.0;         // 1 / I (about the hinge axis for a hinge)
  double k = 0.0;             // angular drag coefficient (N m s)
  Vec3 axis = Vec3::UnitZ();  // hinge axis in P
  double hinge = 0.0;         // 1 for a hinge, 0 for a free isotropic body

  // I^-1 tau, projected onto the hinge axis for a hinge (branch-free).
  Vec3 alpha(const Vec3& tau) const { return inv_I * (tau - hinge * (tau - axis * axis.dot(tau))); }
  // The spin is w_P itself.
  Vec3 omega(const Vec3& spin) const { return spin; }
  Vec3 spin_of(const Vec3& w) const { return w; }
  // d spin / dt under a torque (no drag): I^-1 tau.
  Vec3 spin_rate(const Vec3& tau) const { return alpha(tau); }
  // Decay rates of the spin under angular drag, per P axis.
  Vec3 drag_rates() const { return Vec3::Constant(k * inv_I); }
};

// Principal moments in P (precession: (A, A, C), symmetry axis z; tumbling: ascending).
struct DiagRot {
  Vec3 I = Vec3::Ones();
  Vec3 inv_I = Vec3::Ones();
  double k = 0.0;

  // The spin is h_P = I w_P.
  Vec3 omega(const Vec3& spin) const { return inv_I.cwiseProduct(spin); }
  Vec3 spin_of(const Vec3& w) const { return I.cwiseProduct(w); }
  // d h / dt under a torque, without the gyroscopic term and drag: tau itself.
  Vec3 spin_rate(const Vec3& tau) const { return tau; }
  // Decay rates of h under angular drag: dh_i/dt = -k w_i = -(k / I_i) h_i.
  Vec3 drag_rates() const { return k * inv_I; }
};

// The steady-spin group's cached rotation increments, four to a block component by component, so
// that the kernel (iso_lanes.hpp) loads each component of four bodies as one vector. get and set
// copy one entry out and in exactly.
class SpinIncrements {
 public:
  void push_back(const Quat& dq) {
    if (size_ % 4 == 0) blocks_.emplace_back();
    set(size_++, dq);
  }
  Quat get(int i) const {
    const IncrementBlock& b = blocks_[static_cast<std::size_t>(i / 4)];
    const int l = i % 4;
    return Quat(b.w[l], b.x[l], b.y[l], b.z[l]);
  }
  void set(int i, const Quat& dq) {
    IncrementBlock& b = blocks_[static_cast<std::size_t>(i / 4)];
    const int l = i % 4;
    b.x[l] = dq.x();
    b.y[l] = dq.y();
    b.z[l] = dq.z();
    b.w[l] = dq.w();
  }
  void swap(int i, int j) {
    const Quat a = get(i);
    set(i, get(j));
    set(j, a);
  }
  // The block holding entries i .. i + 3 (i a multiple of 4).
  const IncrementBlock* block(int i) const { return &blocks_[static_cast<std::size_t>(i / 4)]; }

 private:
  std::vector<IncrementBlock> blocks_;
  int size_ = 0;
};

// The axisymmetric rotors' cached plans, one per entry.
class PrecessionPlans {
 public:
  void push_back() { plans_.emplace_back(); }
  AxisymPlan& operator[](int i) { return plans_[static_cast<std::size_t>(i)]; }
  const AxisymPlan& operator[](int i) const { return plans_[static_cast<std::size_t>(i)]; }
  void swap(int i, int j) { std::swap((*this)[i], (*this)[j]); }

 private:
  std::vector<AxisymPlan> plans_;
};

// The exact rotor's constants depend on the principal moments alone and are read only when a plan
// is made: one per distinct moments, found through the body's DiagRot row (of_rot[rot row]), so a
// body pays no index of its own for them and a world of one kind of body pays for one.
struct Rotors {
  std::vector<RotorInertia> values;
  std::vector<std::int32_t> of_rot;  // per row of the group's rot table
};

// A member a kind of group does not have.
struct None {};

// What each kind of group has beyond translation: its rotational parameters (Rot), whether its P
// may differ from B (kPrincipalFrame: a q_BP table), and its exact-drift cache (Plans: the drift
// over the model's dt for the momentum as it is, valid until something changes the momentum).
template <BodyMotion K>
struct GroupTraits;
template <>
struct GroupTraits<BodyMotion::kTranslation> {
  static constexpr bool kTurns = false;
  static constexpr bool kPrincipalFrame = false;
  using Rot = None;
  using Plans = None;
};
template <>
struct GroupTraits<BodyMotion::kSteadySpin> {
  static constexpr bool kTurns = true;
  static constexpr bool kPrincipalFrame = false;  // every frame of an isotropic body is principal
  using Rot = SpinRot;
  using Plans = SpinIncrements;  // exp(h w)
};
template <>
struct GroupTraits<BodyMotion::kPrecession> {
  static constexpr bool kTurns = true;
  static constexpr bool kPrincipalFrame = true;
  using Rot = DiagRot;
  using Plans = PrecessionPlans;
};
template <>
struct GroupTraits<BodyMotion::kTumbling> {
  static constexpr bool kTurns = true;
  static constexpr bool kPrincipalFrame = true;
  using Rot = DiagRot;
  // Structure of arrays, as the lanes kernel reads them (rotor_plans.hpp).
  using Plans = RotorPlans;
};

template <BodyMotion K>
using GroupTag = std::integral_constant<BodyMotion, K>;
inline constexpr GroupTag<BodyMotion::kTranslation> kTranslationGroup{};
inline constexpr GroupTag<BodyMotion::kSteadySpin> kSteadySpinGroup{};
inline constexpr GroupTag<BodyMotion::kPrecession> kPrecessionGroup{};
inline constexpr GroupTag<BodyMotion::kTumbling> kTumblingGroup{};
// A group's place in the per-group arrays (Model::groups, Data::groups, Share).
constexpr int index(BodyMotion k) {
  return static_cast<int>(k);
}

// f(GroupTag<k>{}): the one switch over the kind of group.
template <class F>
decltype(auto) visit(BodyMotion k, F&& f) {
  switch (k) {
    case BodyMotion::kTranslation:
      return f(GroupTag<BodyMotion::kTranslation>{});
    case BodyMotion::kSteadySpin:
      return f(GroupTag<BodyMotion::kSteadySpin>{});
    case BodyMotion::kPrecession:
      return f(GroupTag<BodyMotion::kPrecession>{});
    case BodyMotion::kTumbling:
      break;
  }
  return f(GroupTag<BodyMotion::kTumbling>{});
}
// f(GroupTag<k>{}) for every kind, in order.
template <class F>
void for_each_group(F&& f) {
  f(GroupTag<BodyMotion::kTranslation>{});
  f(GroupTag<BodyMotion::kSteadySpin>{});
  f(GroupTag<BodyMotion::kPrecession>{});
  f(GroupTag<BodyMotion::kTumbling>{});
}

// A group's parameter tables (the Model's): row 0 of `linear` is a still body's (all zero), where
// the guard's frozen bodies point.
template <BodyMotion K>
struct GroupParams {
  using Traits = GroupTraits<K>;
  std::vector<Linear> linear;
  std::conditional_t<Traits::kTurns, std::vector<typename Traits::Rot>, None> rot;
  // Cold, read only at the API's edges and by write_states: the rotation from P to B (bodies with
  // the same inertia matrix have the same one).
  std::conditional_t<Traits::kPrincipalFrame, std::vector<Quat>, None> q_BP;
  std::conditional_t<K == BodyMotion::kTumbling, Rotors, None> rotors;
};

// What every group keeps per entry: structure of arrays over its bodies, in two runs:
// [0, quiet_end) the bodies whose loads leave them quiet (Loads::quiet(): nothing turns them), then
// the loaded ones. A body moves between the runs (world_groups.cpp: place, a swap with the boundary
// entry) when its loads start or stop, so that an integrator with a path for each kind loops over
// each run without a per-body branch. Bodies are independent: their order changes no result.
struct Entries {
  int quiet_end = 0;
  // How many entries of the quiet run have a force in W (f_W not all zero bits): when none has,
  // the quiet translation reads no loads at all (translate_quiet; reading each body's 32 B head
  // was a tenth to a sixth of a free sphere's step). set_load and place keep it.
  int quiet_pushed = 0;
  std::vector<int> id;  // body id of each entry
  std::vector<Motion> motion;
  std::vector<std::int32_t> linear;  // its row of GroupParams::linear
  // Spec loads + applied loads, in P (loads.hpp: LoadHead): per entry the head, and the terms of
  // the entries that have any in a pool, entry 0 all zero. Entries [1, shared_end) are the
  // scene's own loads' terms, once per distinct value (Model::scene_loads), written when the world
  // is built and shared read-only by every body whose loads are its scene's (a scene's thrusters
  // are usually alike: 10^6 of them pay for one); a body given other loads takes an entry of its
  // own. They stay in this pool beside the bodies' own, rather than in the Model, so that a kernel
  // reads every body's terms from one array. The pool's capacity is reserved for every body when
  // the world is built (reserve_terms), so that giving a body terms while stepping never
  // allocates; capacity never used is never touched, so it takes no memory.
  std::vector<LoadHead> loads;
  std::vector<LoadTerms> terms;
  std::int32_t shared_end = 1;
  std::vector<std::int32_t> free_terms;  // own entries given back, capacity reserved
  int size() const { return static_cast<int>(id.size()); }

  LoadsRef load(int i) const {
    const LoadHead& h = loads[i];
    return LoadsRef(h, terms[h.terms]);
  }
  Loads load_value(int i) const {
    const LoadsRef r = load(i);
    Loads v;
    v.flags = r.flags;
    v.f_W = r.f_W;
    v.f_P = r.f_P;
    v.tau_P = r.tau_P;
    v.tau_W = r.tau_W;
    v.fr = r.fr;
    return v;
  }
  // Stores v as entry i's loads: its terms take a pool entry of its own if they are not all zero,
  // and give it back otherwise; or, with `shared` (an entry of [1, shared_end) that holds exactly
  // v's terms: add_shared_terms), point at that entry. Allocation-free once reserve_terms has run.
  void set_load(int i, const Loads& v, std::int32_t shared = 0) {
    LoadHead& h = loads[i];
    if (i < quiet_end) quiet_pushed += int{pushed(v.f_W)} - int{pushed(h.f_W)};
    h.flags = v.flags;
    h.f_W = v.f_W;
    if ((v.flags & LoadFlags::kTerms) == 0 || shared != 0) {
      if (h.terms >= shared_end) free_terms.push_back(h.terms);
      h.terms = (v.flags & LoadFlags::kTerms) == 0 ? 0 : shared;
      return;
    }
    if (h.terms < shared_end) {  // none, or shared: never written through
      if (free_terms.empty()) {
        h.terms = static_cast<std::int32_t>(terms.size());
        terms.emplace_back();
      } else {
        h.terms = free_terms.back();
        free_terms.pop_back();
      }
    }
    LoadTerms& t = terms[h.terms];
    t.f_P = v.f_P;
    t.tau_P = v.tau_P;
    t.tau_W = v.tau_W;
    t.fr = v.fr;
  }
  // Whether a force in W counts as one for quiet_pushed: any bit set, so that only +0.0 (what the
  // kernel then uses instead) does not.
  static bool pushed(const Vec3& f_W) {
    std::uint64_t bits[3];
    std::memcpy(bits, f_W.data(), sizeof bits);
    return (bits[0] | bits[1] | bits[2]) != 0;
  }
  // A shared entry holding v's terms, for set_load's `shared`: made while the world is built,
  // before reserve_terms (all of them before any body's own entry).
  std::int32_t add_shared_terms(const Loads& v) {
    if (terms.empty()) terms.emplace_back();
    terms.push_back(LoadTerms{.f_P = v.f_P, .tau_P = v.tau_P, .tau_W = v.tau_W, .fr = v.fr});
    shared_end = static_cast<std::int32_t>(terms.size());
    return shared_end - 1;
  }
  // Capacity for every entry to have terms of its own at once (besides the zero and shared ones).
  void reserve_terms() {
    if (terms.empty()) terms.emplace_back();
    terms.reserve(id.size() + static_cast<std::size_t>(shared_end));
    free_terms.reserve(id.size());
  }
};

// A group's entries (the Data's): what every group keeps, and per entry its rows of the group's
// rotation and q_BP tables and its exact-drift cache (plan_ok[i]: whether plan i is valid), where
// the kind has them.
template <BodyMotion K>
struct GroupEntries : Entries {
  using Traits = GroupTraits<K>;
  std::conditional_t<Traits::kTurns, std::vector<std::int32_t>, None> rot;
  std::conditional_t<Traits::kPrincipalFrame, std::vector<std::int32_t>, None> q_BP;
  typename Traits::Plans plan;
  std::conditional_t<Traits::kTurns, std::vector<std::uint8_t>, None> plan_ok;

  // Exchanges entries a and b, everything of each (their bodies' slots are the caller's).
  void swap(int a, int b) {
    const auto sw = [&](auto& v) { std::swap(v[a], v[b]); };
    sw(id);
    sw(motion);
    sw(linear);
    sw(loads);
    if constexpr (Traits::kTurns) {
      sw(rot);
      plan.swap(a, b);
      sw(plan_ok);
    }
    if constexpr (Traits::kPrincipalFrame) sw(q_BP);
  }
};

// A group's parameters and entries together (data.hpp: group(model, data, kind)): entry i's rows
// of the parameter tables read through its entries, g.rot(i) = params.rot[entries.rot[i]]. Two
// references, passed by value. E: GroupEntries<K>, or const GroupEntries<K> for a view that reads
// only.
template <BodyMotion K, class E = GroupEntries<K>>
struct Group {
  using Traits = GroupTraits<K>;
  static constexpr BodyMotion kKind = K;
  static constexpr int kIndex = index(K);
  const GroupParams<K>& params;
  E& entries;

  int size() const { return entries.size(); }
  auto& motion(int i) const { return entries.motion[i]; }
  const Linear& linear(int i) const { return params.linear[entries.linear[i]]; }
  const auto& rot(int i) const requires Traits::kTurns { return params.rot[entries.rot[i]]; }
  const Quat& q_BP(int i) const requires Traits::kPrincipalFrame {
    return params.q_BP[entries.q_BP[i]];
  }
  const RotorInertia& rotor(int i) const requires(K == BodyMotion::kTumbling) {
    return params.rotors.values[params.rotors.of_rot[entries.rot[i]]];
  }
  LoadsRef load(int i) const { return entries.load(i); }
};
template <BodyMotion K>
using ConstGroup = Group<K, const GroupEntries<K>>;

// Entry i's rotational parameters, or None for a group that never turns: for a kernel that names
// them once per body and reads them only where the group turns.
template <class G>
const auto& rot_or_none(const G& g, int i) {
  if constexpr (G::Traits::kTurns) {
    return g.rot(i);
  } else {
    (void)g, (void)i;
    static constexpr None kNone{};
    return kNone;
  }
}

using TranslationGroup = Group<BodyMotion::kTranslation>;
using SteadySpinGroup = Group<BodyMotion::kSteadySpin>;
using PrecessionGroup = Group<BodyMotion::kPrecession>;
using TumblingGroup = Group<BodyMotion::kTumbling>;

}  // namespace rigid::physics::detail
