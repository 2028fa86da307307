// The static geometry of a world, compiled: infinite planes and placed convex shapes that never
// move and have no mass, each with its material.
#pragma once

#include <algorithm>
#include <cmath>

#include "physics/contact/support.hpp"
#include "physics/math.hpp"
#include "physics/spec.hpp"

namespace rigid::physics::contact {

using physics::Surface;  // spec.hpp

// The pair's values from each side's: the larger restitution, so that a bouncy body bounces on
// any floor and a dead one stays dead only on a dead floor (restitution is a property of the
// impact, and the livelier partner stores and returns the energy); the geometric mean of friction,
// so that a frictionless side makes the pair frictionless, equal materials keep their value, and
// the result does not depend on which side is which.
inline Surface combine(const Surface& a, const Surface& b) {
  return Surface{std::max(a.restitution, b.restitution), std::sqrt(a.friction * b.friction)};
}

struct StaticPart {
  enum class Kind { kPlane, kShape };
  Kind kind = Kind::kPlane;
  // A plane: the half-space n_W . x <= offset is solid (n_W unit, pointing out of it).
  Vec3 n_W = Vec3::UnitZ();
  double offset = 0.0;
  // A shape: its convex collision shape, placed at p_WS with orientation q_WS.
  Convex convex;
  Vec3 p_WS = Vec3::Zero();
  Quat q_WS = Quat::Identity();
  Surface surface;
};

}  // namespace rigid::physics::contact
