// The compiled world's changing half (as MuJoCo's mjData): the bodies' motion and loads in their
// groups' entries, and what the World keeps between steps (pending impulses, bodies to regroup, the
// guard's poses, the step count). The step functions write it; the Model (model.hpp) they read.
// A world of 10^6 bodies pays for every byte kept per body here a million times
// (bench/physics/memory_bench.cpp): per body it is kept to what cannot be derived again from the
// Model.
#pragma once

#include <cstdint>
#include <tuple>
#include <vector>

#include "physics/model.hpp"

namespace rigid::physics::detail {

// An impulse waiting for the next step.
struct PendingImpulse {
  int id = 0;
  Vec3 J = Vec3::Zero();  // impulse (W)
  Vec3 L = Vec3::Zero();  // its angular momentum about the centre of mass (W)
};

// A body's pose at the guard's last check (World::frozen_bodies). Unaligned doubles: 56 B, where
// an aligned Quat and a Vec3 take 64.
struct GuardPose {
  double q[4] = {0.0, 0.0, 0.0, 1.0};  // x, y, z, w as Quat::coeffs()
  double x[3] = {0.0, 0.0, 0.0};
  GuardPose() = default;
  GuardPose(const Quat& r, const Vec3& p) : q{r.x(), r.y(), r.z(), r.w()}, x{p.x(), p.y(), p.z()} {}
  Quat quat() const { return Quat(q[3], q[0], q[1], q[2]); }
  Vec3 pos() const { return Vec3(x[0], x[1], x[2]); }
};

struct Data {
  // Per group its entries (groups.hpp), by index(kind).
  std::tuple<GroupEntries<BodyMotion::kTranslation>, GroupEntries<BodyMotion::kSteadySpin>,
             GroupEntries<BodyMotion::kPrecession>, GroupEntries<BodyMotion::kTumbling>>
      groups;
  // Per body id its entry in its group (Model::motion names the group); regrouping moves it.
  std::vector<std::int32_t> entry;
  // Impulses waiting for the next step: per body the index of its entry in `pending` or -1, the
  // entries in order of arrival (capacity reserved for every body, so that apply_impulse never
  // allocates; untouched capacity is never resident).
  std::vector<int> pending_slot;
  std::vector<PendingImpulse> pending;
  // Bodies whose loads may have moved them between the quiet and the loaded run of their group
  // (groups.hpp), placed at the start of the next step (capacity reserved: no allocation).
  std::vector<int> regroup_ids;
  std::vector<std::uint8_t> regroup_flag;
  // The guard (World::frozen_bodies): the pose of each body's last state that passed the check (a
  // frozen body is put back there at rest, so its velocities need no copy), and who is frozen, in
  // order, with the row of its translation parameters before the freeze (frozen_linear; the
  // freeze points it at row 0, a still body's). Capacities reserved: no allocation.
  std::vector<GuardPose> last_good;
  std::vector<std::uint8_t> frozen;
  std::vector<int> frozen_ids;
  std::vector<std::int32_t> frozen_linear;
  std::int64_t steps = 0;
  // Body-steps in which a body turned by more than pi under an integrator that is not exact for
  // large rotations (all but the exact-rotor splittings): counted so that callers can report
  // them; the step itself is taken as the scheme defines it, never clamped. The sum of the
  // threads' Share::large_rotations, added after each step.
  std::int64_t large_rotations = 0;
  // How bodies meet the static geometry (contact/contact_world.hpp); empty without any.
  ContactData contact;

  template <BodyMotion K>
  GroupEntries<K>& entries(GroupTag<K> = {}) {
    return std::get<index(K)>(groups);
  }
  template <BodyMotion K>
  const GroupEntries<K>& entries(GroupTag<K> = {}) const {
    return std::get<index(K)>(groups);
  }
};

// Group K of a world: its parameters (the Model's) with its entries (the Data's).
template <BodyMotion K>
Group<K> group(const Model& m, Data& d, GroupTag<K> k = {}) {
  return {m.params(k), d.entries(k)};
}
template <BodyMotion K>
ConstGroup<K> group(const Model& m, const Data& d, GroupTag<K> k = {}) {
  return {m.params(k), d.entries(k)};
}

}  // namespace rigid::physics::detail
