// A convex shape's support mapping, the one description of its geometry the contact code reads:
// every query (distance to a plane, the closest points of two shapes, the features that touch)
// is built on h(u) = max_{x in S} u.x and on the point that attains it (Gilbert, Johnson &
// Keerthi, IEEE J. Robotics and Automation 4(2), 1988; van den Bergen, "Collision Detection in
// Interactive 3D Environments", 2004, ch. 4).
//
// A collision shape is a physics::Shape centred on its body's centre of mass with its axes along
// B (the inertia's convention, inertia.hpp), or nothing: a body without a shape collides as a
// point. Each shape is split into a core and a radius (a sphere is a point of radius r, a capsule
// a segment of radius r), so that the distance of two shapes is that of their cores less the
// radii: exact for the rounded shapes, where a core-less search would only converge to it.
#pragma once

#include <array>
#include <optional>

#include "physics/inertia.hpp"
#include "physics/math.hpp"

namespace rigid::physics::contact {

// What a collision shape is, reduced to what its support mapping needs. `half` holds half sizes:
// box half extents; sphere (0, 0, 0) core and radius r; capsule core half length on z and radius;
// cylinder radius and half length (no radius: its rim is sharp); ellipsoid semi-axes.
struct Convex {
  enum class Kind { kPoint, kSphere, kBox, kCapsule, kCylinder, kEllipsoid };
  Kind kind = Kind::kPoint;
  Vec3 half = Vec3::Zero();
  double radius = 0.0;  // the rounding: sphere and capsule

  // The collision shape of a body's (or a static part's) shape; a point without one.
  static Convex of(const std::optional<Shape>& shape);
  // Support of the core along u (in the shape's frame; u need not be unit): the core's point
  // farthest along u. Ties resolve to the positive side (a face's +x corner), deterministically.
  Vec3 core_support(const Vec3& u) const;
  // h of the core along a unit u.
  double core_height(const Vec3& u) const;
  // h of the whole shape along a unit u: core_height + radius.
  double height(const Vec3& u) const { return core_height(u) + radius; }
  // The largest distance of any point of the shape from its centre.
  double bounding_radius() const;
};

// The points of the shape (in its frame) that lie within `tol` of its support plane along the
// unit u: where a shape pressed against a plane of inward normal -u touches it. A vertex, an
// edge's two ends, a face's corners; a flat disk (a cylinder's end) as kDiskPoints points of its
// rim; a capsule or cylinder lying along the plane as the two ends of its touching line. At most
// kMaxFeature points; returns how many.
inline constexpr int kDiskPoints = 8;
inline constexpr int kMaxFeature = 8;
int touching_points(const Convex& c, const Vec3& u, double tol, std::array<Vec3, kMaxFeature>& out);

}  // namespace rigid::physics::contact
