// What every peer driver reads off a hard case's body, checked once here: the peers are given a
// diagonal inertia in the body frame, so a case must use principal axes as its body frame, and
// nothing the drivers do not translate (kinematic bodies, frozen axes, point masses).
#pragma once

#include "hard_cases.hpp"

namespace rigid::bench::peers {

// The principal moments (the diagonal of I_B). Throws std::runtime_error when the case's body is
// not one every driver can represent exactly.
Vec3 principal_moments(const Case& c);

// Whether any load is expressed in the body frame (it turns with the body).
bool has_body_frame_load(const Case& c);

// Whether the body has linear or angular drag.
bool has_drag(const Case& c);

}  // namespace rigid::bench::peers
