// How far a body is from a static part, which way it would touch it, and where.
#pragma once

#include <array>

#include "physics/contact/gjk.hpp"
#include "physics/contact/static_part.hpp"
#include "physics/contact/support.hpp"

namespace rigid::physics::contact {

// A body's placement: the origin of B (its centre of mass) and B's orientation, in W.
struct Pose {
  Vec3 p_WBo = Vec3::Zero();
  Quat q_WB = Quat::Identity();
};

// The separation of a body from a static part: the distance between the surfaces (>= 0 while
// apart), the unit normal from the part towards the body, and the closest point on the body's
// surface (W).
struct Gap {
  double distance = 0.0;
  Vec3 n_W = Vec3::UnitZ();
  Vec3 p_W = Vec3::Zero();
};

// The signed gap to a plane (negative inside it) and the body's point deepest towards it; exact:
// n . p_WBo - h(R_BW n) - offset.
Gap plane_gap(const Convex& body, const Pose& pose, const StaticPart& plane);
// The gap to a placed shape: the cores' distance (gjk.hpp) less both radii, with the normal of
// the closest points. Where the cores touch (the rounded shapes never do), the normal is taken
// from the pose backed off along the centres' line, where it is well defined.
Gap shape_gap(const Convex& body, const Pose& pose, const StaticPart& part);
inline Gap gap(const Convex& body, const Pose& pose, const StaticPart& part) {
  return part.kind == StaticPart::Kind::kPlane ? plane_gap(body, pose, part)
                                               : shape_gap(body, pose, part);
}

// The points where a body touching a static part along gap g touches it (W), all of the body's
// surface within `tol` of the closest point's level along the normal and, for a placed shape,
// within `tol` of the part: one point, an edge's ends, a face's corners (support.hpp). Returns
// how many (at least 1).
int touching_points(const Convex& body, const Pose& pose, const StaticPart& part, const Gap& g,
                    double tol, std::array<Vec3, kMaxFeature>& out);

}  // namespace rigid::physics::contact
