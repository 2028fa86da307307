// How far two bodies are apart, which way they would touch, and where: the body-body counterpart
// of gap.hpp.
#pragma once

#include <array>

#include "physics/contact/gap.hpp"
#include "physics/contact/support.hpp"

namespace rigid::physics::contact {

// The separation of body a from body b: the distance between their surfaces (>= 0 while apart),
// the unit normal from b towards a, and the closest points on each surface (W).
struct PairGap {
  double distance = 0.0;
  Vec3 n_W = Vec3::UnitZ();
  Vec3 p_a_W = Vec3::Zero(), p_b_W = Vec3::Zero();
};

// Spheres and points in closed form (the centres' distance less the radii); every other pair by
// the cores' distance (gjk.hpp) less both radii, with the normal of the closest points, taken
// where the cores touch from a pose backed off along the centres' line, as shape_gap does.
PairGap pair_gap(const Convex& a, const Pose& pa, const Convex& b, const Pose& pb);

// Where a and b touch along g's normal: the features of each within `tol` of its support plane
// (support.hpp's touching_points: a corner, an edge, a face, a disk, a line), overlapped in the
// contact plane (a face on a face is their clipped polygon, up to kMaxFeature corners; an edge on a
// face is its clipped segment; a point is itself). Each point lies midway between the two
// surfaces there. Returns how many (at least 1).
int pair_manifold(const Convex& a, const Pose& pa, const Convex& b, const Pose& pb,
                  const PairGap& g, double tol, std::array<Vec3, kMaxFeature>& out);

}  // namespace rigid::physics::contact
