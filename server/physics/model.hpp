// The compiled world's constant half (as MuJoCo's mjModel): everything the World's build derives
// from the WorldSpec and never changes afterwards. Every step function takes it const; the World
// and its copies share one (world_impl.hpp). What changes while stepping is the Data (data.hpp).
#pragma once

#include <array>
#include <cstdint>
#include <tuple>
#include <vector>

#include "physics/contact/contact_world.hpp"
#include "physics/groups.hpp"
#include "physics/integrator.hpp"
#include "physics/spec_store.hpp"
#include "physics/translation.hpp"

namespace rigid::physics::detail {

// Step sizes for which translation coefficients are tabulated (composition stages included):
// Suzuki's two stage sizes (exact_rotor4), then the triple jump's (TripleJump: hybrid4's loaded
// bodies).
enum TransSize : int { kFull, kHalf, kStage0, kStage1, kForced0, kForced1, kNumSizes };

// Translation coefficients per distinct drag rate, so that stepping needs no exp().
struct TransTable {
  std::vector<double> gamma;
  std::vector<std::array<TransCoef, kNumSizes>> coef;
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

// Yoshida's triple jump (Yoshida, Phys. Lett. A 150, 1990; Creutz & Gocksch 1989): the cheapest
// symmetric composition of a symmetric second-order step into fourth order, stages
// (g1, g0, g1) with g1 = 1 / (2 - 2^(1/3)), g0 = 1 - 2 g1.
struct TripleJump {
  static constexpr int kStages = 3;
  static constexpr double kG1 = 1.35120719195965763405;
  static constexpr double kStage[kStages] = {kG1, 1.0 - 2.0 * kG1, kG1};
  static constexpr TransSize kSize[kStages] = {kForced0, kForced1, kForced0};
};

// The scene's own loads (in P), to which a body's loads go back when applied ones are cleared: of
// the bodies that have any (or angular drag, which Loads flags), ascending ids, and per id its
// entry in `values`, where equal loads are kept once (scenes give many bodies the same thruster or
// drag). Most bodies have none, and a dense copy cost 176 B each.
struct SceneLoads {
  std::vector<int> ids;
  std::vector<std::int32_t> of;
  std::vector<Loads> values;
  // Per entry of `values`, the shared entry of its terms in its bodies' group's pool
  // (Entries::terms; 0: it has none), made when the Data is built. An entry's bodies are all of
  // one group.
  std::vector<std::int32_t> terms;

  // Body id's entry of `values`, or -1: it has no loads of its own in the scene.
  int index(int id) const;
};

struct Model {
  double dt = 1e-3;
  // Lanes of the batched kernels (hybrid_lanes.hpp, rotor_lanes.hpp): 8, 4 or 2, chosen for the CPU
  // when the world is built; every width gives the same states. 1: the scalar code (tests).
  int lanes = 2;
  Vec3 g_W = Vec3::Zero();
  const IntegratorInfo* integrator = nullptr;
  TransTable trans;
  // Per group its parameter tables (groups.hpp), by index(kind).
  std::tuple<GroupParams<BodyMotion::kTranslation>, GroupParams<BodyMotion::kSteadySpin>,
             GroupParams<BodyMotion::kPrecession>, GroupParams<BodyMotion::kTumbling>>
      groups;
  // Per body id its group. Its motion type and allowed degrees of freedom are among its
  // parameters in `specs` (SpecStore::Params), kept once per distinct value.
  std::vector<BodyMotion> motion;
  // Cold, read by the API, reset and the guard: the bodies' specs, validated, orientations
  // normalised (spec_store.hpp), body ids in ascending order of name (find_body: a hash map of the
  // names cost ~70 B a body), and the scene's loads.
  SpecStore specs;
  std::vector<int> by_name;
  SceneLoads scene_loads;
  // Static geometry and what bodies need to meet it (contact/contact_world.hpp); empty without.
  ContactModel contact;

  int body_count() const { return static_cast<int>(motion.size()); }
  template <BodyMotion K>
  const GroupParams<K>& params(GroupTag<K> = {}) const {
    return std::get<index(K)>(groups);
  }
  template <BodyMotion K>
  GroupParams<K>& params(GroupTag<K> = {}) {
    return std::get<index(K)>(groups);
  }
  const TransCoef& tc(const Linear& l, TransSize s) const { return trans.coef[l.drag][s]; }
};

// Fills the translation table for the model's dt.
void build_trans_table(Model& m);

}  // namespace rigid::physics::detail
