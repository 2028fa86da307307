// The scene's bodies as World keeps them after compiling: cold data, read by reset(), body_spec(),
// find_body() and the API's edges, never by a step. A BodySpec is 256 B (its name's std::string,
// a 3x3 inertia, Eigen's alignment); kept as it is, the copies were a quarter of a general body's
// memory and half a point mass's (bench/physics/memory_bench.cpp). Here a body costs its name's
// bytes in one buffer and a 4 B offset, its initial position (24 B), and two indices: of its
// parameters (mass, inertia, drags, flags: a scene of 10^6 bodies usually has a handful of kinds)
// and of its initial orientation and velocities (80 B: a large scene's bodies usually start alike,
// at rest or all turning the same way), each kept once per distinct value: ~40 B, and 4 B more than
// a dense copy of the initial state for a scene whose bodies all start differently. get(id) gives
// back the BodySpec it was given, bit for bit, but for its orientation, which is kept normalised
// (World validates that it can be).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "physics/body_motion.hpp"
#include "physics/spec.hpp"

namespace rigid::physics::detail {

class SpecStore {
 public:
  // Everything of a BodySpec but its name and its initial state; its kinematic flag and frozen
  // axes as the body's motion type and allowed degrees of freedom (body_motion.hpp).
  struct Params {
    double mass = 1.0;
    Mat3 I_B = Mat3::Identity();
    double linear_drag = 0.0;
    double angular_drag = 0.0;
    bool has_inertia = true;
    bool use_gravity = true;
    MotionType motion_type = MotionType::kDynamic;
    AllowedDofs allowed_dofs = AllowedDofs::kAll;
    bool kinematic() const { return motion_type == MotionType::kKinematic; }
  };

  // Keeps a copy of `bodies`, orientations normalised.
  explicit SpecStore(const std::vector<BodySpec>& bodies);
  SpecStore() = default;

  // The most bytes all names together may take (World refuses more: SpecError on "name").
  static constexpr std::uint64_t kMaxNameBytes = UINT32_MAX;

  int size() const { return static_cast<int>(p_.size()); }
  std::string_view name(int id) const {
    const std::uint32_t b = id == 0 ? 0 : name_end_[id - 1];
    return std::string_view(names_).substr(b, name_end_[id] - b);
  }
  const Params& params(int id) const { return params_[params_of_[id]]; }
  // The spec's initial state.
  Vec3 p_WBo(int id) const { return Vec3(p_[id].data()); }
  Quat q_WB(int id) const {
    const double* q = start(id).q;
    return Quat(q[0], q[1], q[2], q[3]);
  }
  Vec3 v_WBo(int id) const { return Vec3(start(id).v); }
  Vec3 w_WB(int id) const { return Vec3(start(id).w); }
  // How many distinct initial orientation-and-velocities the bodies have (tests).
  int distinct_starts() const { return static_cast<int>(starts_.size()); }
  // The BodySpec of body id, as given.
  BodySpec get(int id) const;

 private:
  // The initial orientation (w, x, y, z) and velocities, unaligned doubles: 80 B.
  struct Start {
    double q[4], v[3], w[3];
  };
  const Start& start(int id) const { return starts_[start_of_[id]]; }

  std::string names_;                     // every name, one after the other
  std::vector<std::uint32_t> name_end_;   // where body id's name ends in names_
  std::vector<std::array<double, 3>> p_;  // by body id: its initial position
  std::vector<std::int32_t> start_of_;    // by body id: its entry in starts_
  std::vector<Start> starts_;             // distinct by their bits
  std::vector<std::int32_t> params_of_;   // by body id: its entry in params_
  std::vector<Params> params_;
};

}  // namespace rigid::physics::detail
