// The compiled world, internal to the physics library: bodies grouped by the cheapest exact model
// for them, each group in contiguous arrays so that an integrator's loop over a group has no
// per-body branch on the kind of body (Box2D v3's solver sets, MuJoCo's model/data split).
//
// Every body's state is kept about its centre of mass in its principal frame P:
//   Motion::q = q_WP, Motion::x = p_WBo, Motion::v = v_WBo (in W), and Motion::spin, expressed in
//   P: the angular velocity w_P for point and isotropic bodies, the angular momentum h_P = I w_P
//   for axisymmetric and general ones. Momentum is what the splittings and the exact rotor evolve
//   and what torque changes directly; keeping it as the state spares every step a round trip h = I
//   w, w = h / I, whose rounding is a fixed bias per axis (I * (1/I) != 1) that a long run
//   accumulates. The rotational parameters below convert (omega, spin_of) where a scheme needs w.
#pragma once

#include <array>
#include <cstdint>
#include <cstring>
#include <vector>

#include "physics/free_rotor.hpp"
#include "physics/iso_lanes.hpp"
#include "physics/loads.hpp"
#include "physics/rotor_plans.hpp"
#include "physics/translation.hpp"

namespace rigid::physics::detail {

struct Motion {
  Quat q = Quat::Identity();
  Vec3 x = Vec3::Zero();
  Vec3 v = Vec3::Zero();
  Vec3 spin = Vec3::Zero();
};

struct Linear {
  Vec3 g = Vec3::Zero();      // gravity, zero on frozen axes and when the body ignores it
  Vec3 inv_m = Vec3::Zero();  // 1/m, zero on frozen axes and for kinematic bodies
  double gamma = 0.0;         // linear drag rate c / m (1/s)
  int drag = 0;               // row of TransTable for this gamma (row 0: gamma = 0)

  Vec3 accel(const Vec3& f_W) const { return g + inv_m.cwiseProduct(f_W); }
};

// Step sizes for which translation coefficients are tabulated (composition stages included):
// Suzuki's two stage sizes (exact_rotor4), then the forced composition's (ForcedComposition).
enum TransSize : int { kFull, kHalf, kStage0, kStage1, kForced0, kForced1, kNumSizes };

// Translation coefficients per distinct drag rate, so that stepping needs no exp().
struct TransTable {
  std::vector<double> gamma;
  std::vector<std::array<TransCoef, kNumSizes>> coef;
};

// Rotational parameters. An isotropic body needs no gyroscopic term; the same group holds the
// bodies whose rotation is frozen to a hinge about one world axis (that axis is fixed in P too,
// and the constraint absorbs every other torque), and kinematic bodies (inv_I = 0).
struct IsoRot {
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

// Principal moments in P (axisymmetric: (A, A, C), symmetry axis z; general: ascending).
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

// Per-body parameters that bodies with equal ones share (World interns them when it is built): a
// 4 B index a body instead of the value (a Linear is 64 B, a DiagRot 56); a world of 10^6 bodies
// usually has a handful of kinds. shared(i) is entry i's value; `of` moves with the entry when
// the runs regroup.
template <class T>
struct Shared {
  std::vector<std::int32_t> of;  // per entry
  std::vector<T> values;
  const T& operator()(int i) const { return values[of[i]]; }
};

// The bodies of one model, structure of arrays over bodies. The entries are kept in two runs:
// [0, quiet_end) the bodies whose loads leave them quiet (Loads::quiet(): nothing turns them), then
// the loaded ones. A body moves between the runs (World::Impl::regroup, a swap with the boundary
// entry) when its loads start or stop, so that an integrator with a path for each kind loops over
// each run without a per-body branch. Bodies are independent: their order changes no result.
struct Group {
  int quiet_end = 0;
  // How many entries of the quiet run have a force in W (f_W not all zero bits): when none has,
  // the quiet translation reads no loads at all (translate_quiet; reading each body's 32 B head
  // was a tenth to a sixth of a free sphere's step). set_load and World::Impl::place keep it.
  int quiet_pushed = 0;
  std::vector<int> id;  // body id of each entry
  std::vector<Motion> motion;
  // Translation parameters, shared (entry 0 all zero: a still body's, where the guard's frozen
  // bodies point).
  Shared<Linear> linear;
  // Spec loads + applied loads, in P (loads.hpp: LoadHead): per entry the head, and the terms of
  // the entries that have any in a pool, entry 0 all zero. Entries [1, shared_end) are the
  // scene's own loads' terms, once per distinct value (World::Impl::base_loads), shared read-only
  // by every body whose loads are its scene's (a scene's thrusters are usually alike: 10^6 of them
  // pay for one); a body given other loads takes an entry of its own. The pool's capacity is
  // reserved for every body when the world is built (reserve_terms), so that giving a body terms
  // while stepping never allocates; capacity never used is never touched, so it takes no memory.
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

struct PointGroup : Group {
  static constexpr int kIndex = 0;
};

// The isotropic bodies' cached rotation increments, four to a block component by component, so
// that the kernel (iso_lanes.hpp) loads each component of four bodies as one vector. get and set
// copy one entry out and in exactly.
class IsoIncrements {
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

struct IsoGroup : Group {
  static constexpr int kIndex = 1;
  Shared<IsoRot> rot;
  // Exact-rotation cache: exp(h w) for the current w, valid while no torque or impulse changes w.
  IsoIncrements dq;
  std::vector<std::uint8_t> dq_ok;
};

struct AxiGroup : Group {
  static constexpr int kIndex = 2;
  Shared<DiagRot> rot;
  std::vector<AxisymPlan> plan;
  std::vector<std::uint8_t> plan_ok;
  // Cold, read only at the API's edges and by write_states: the rotation from P to B, shared
  // (bodies with the same inertia matrix have the same one: a 4 B index a body instead of 32),
  // and only by the models whose P is not B.
  Shared<Quat> q_BP;
};

struct GenGroup : Group {
  static constexpr int kIndex = 3;
  Shared<DiagRot> rot;
  // The exact rotor's constants depend on the principal moments alone and are read only when a
  // plan is made: one per distinct moments (rotors), found through the body's DiagRot entry
  // (rotor_of_rot[rot.of[i]]), so a body pays no index of its own for them and a world of one
  // kind of body pays for one.
  std::vector<RotorInertia> rotors;
  std::vector<std::int32_t> rotor_of_rot;  // per entry of rot.values
  const RotorInertia& rotor_of(int i) const { return rotors[rotor_of_rot[rot.of[i]]]; }
  RotorPlans plan;  // structure of arrays, as the lanes kernel reads them (rotor_plans.hpp)
  std::vector<std::uint8_t> plan_ok;
  Shared<Quat> q_BP;  // as AxiGroup::q_BP
};

// A composition of a symmetric second-order step into a fourth-order one: stage sizes c_i h.
// Suzuki's fractal (Suzuki, Phys. Lett. A 146, 1990): p = 1 / (4 - 4^(1/3)), stages
// (p, p, 1 - 4p, p, p); all five are symmetric about the middle, so the result stays symmetric.
struct Composition {
  static constexpr int kStages = 5;
  static constexpr double kP = 0.41449077179437573714;
  static constexpr double kStage[kStages] = {kP, kP, 1.0 - 4.0 * kP, kP, kP};
  static constexpr TransSize kSize[kStages] = {kStage0, kStage0, kStage1, kStage0, kStage0};
};

// A run of entries of one group, [begin, end).
struct Range {
  int begin = 0, end = 0;
};

// One chunk of a step's work, which one thread claims and does (pool.hpp): per group (by kIndex),
// a contiguous slice of all its entries (for integrators with one path), and a slice of each run
// (quiet, loaded) for those with a path per kind. The slices of all chunks cover each group
// exactly once; a body's arithmetic never depends on which thread or slice steps it, so states are
// bit-identical for any number of threads.
struct Share {
  Range all[4];
  Range run[4][2];  // [group][0: quiet, 1: loaded]
  // Body-steps of this share in which a body turned by more than pi (see Model::large_rotations).
  std::int64_t large_rotations = 0;
  // Caches made by fill_quiet_caches (kernels.hpp) in this share.
  std::int64_t caches_made = 0;

  // Counts a step of angle |w| dt > pi.
  void note_rotation(double dt, const Vec3& w) {
    constexpr double kPi2 = 9.8696044010893586188;  // pi^2
    if (dt * dt * w.squaredNorm() > kPi2) ++large_rotations;
  }
};

// Yoshida's triple jump (Yoshida, Phys. Lett. A 150, 1990; Creutz & Gocksch 1989): the cheapest
// symmetric composition of a symmetric second-order step into fourth order, stages
// (g1, g0, g1) with g1 = 1 / (2 - 2^(1/3)), g0 = 1 - 2 g1.
struct TripleJump {
  static constexpr int kStages = 3;
  static constexpr double kG1 = 1.35120719195965763405;
  static constexpr double kStage[kStages] = {kG1, 1.0 - 2.0 * kG1, kG1};
  static constexpr TransSize kSize[kStages] = {kForced0, kForced1, kForced0};
};

struct Model {
  double dt = 1e-3;
  // Lanes of the batched kernels (hybrid_lanes.hpp, rotor_lanes.hpp): 8, 4 or 2, chosen for the CPU
  // when the world is built; every width gives the same states. 1: the scalar code (tests).
  int lanes = 2;
  // Body-steps in which a body turned by more than pi under an integrator that is not exact for
  // large rotations (all but the exact-rotor splittings): counted so that callers can report
  // them; the step itself is taken as the scheme defines it, never clamped. The sum of the
  // threads' Share::large_rotations, added after each step.
  std::int64_t large_rotations = 0;
  PointGroup point;
  IsoGroup iso;
  AxiGroup axi;
  GenGroup gen;
  TransTable trans;

  const TransCoef& tc(const Linear& l, TransSize s) const { return trans.coef[l.drag][s]; }
};

// The translation parameters of consecutive entries of a group and their coefficients for one
// step size, fetched again only when an entry's index differs from the last one's. Bodies mostly
// share a few entries, so the quiet loops load a 4 B index a body instead of following it to the
// shared entry and on to its drag row each time.
class LinearCursor {
 public:
  LinearCursor(const Group& g, const Model& m, TransSize size) : g_(g), m_(m), size_(size) {}
  void at(int i) {
    const int k = g_.linear.of[i];
    if (k == k_) return;
    k_ = k;
    lin_ = g_.linear.values[k];
    tc_ = m_.tc(lin_, size_);
  }
  const Linear& lin() const { return lin_; }
  const TransCoef& tc() const { return tc_; }

 private:
  const Group& g_;
  const Model& m_;
  TransSize size_;
  int k_ = -1;
  Linear lin_;
  TransCoef tc_;
};

// Fills the translation table for the model's dt.
void build_trans_table(Model& m);

}  // namespace rigid::physics::detail
