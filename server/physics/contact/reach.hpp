// When a body could first touch any static part: so that a body far from every part is not looked
// at again until then, and a scene's bodies in free flight cost the contact stage nothing between.
//
// From a lower bound D on the distance between the body's bounding sphere and the parts, and
// bounds on its speed |v| and acceleration A over the time ahead, it cannot touch before
//   t = D / |v|                           (A = 0)
//   t = 2 D / (|v| + sqrt(|v|^2 + 2 A D)) (the root of D = |v| t + A t^2 / 2, without
//                                          cancellation)
// The bound holds while the body's loads stay what they are (gravity, its scene loads, applied
// ones): the World looks again at once when they change.
#pragma once

#include <cmath>
#include <limits>
#include <span>

#include "physics/contact/static_part.hpp"
#include "physics/math.hpp"

namespace rigid::physics::contact {

// A lower bound of the distance from a sphere (centre c, radius rho) to the nearest part.
inline double clearance(std::span<const StaticPart> parts, const Vec3& c, double rho) {
  double d = std::numeric_limits<double>::infinity();
  for (const StaticPart& p : parts) {
    const double dp = p.kind == StaticPart::Kind::kPlane
                          ? p.n_W.dot(c) - p.offset - rho
                          : (c - p.p_WS).norm() - rho - p.convex.bounding_radius();
    d = std::min(d, dp);
  }
  return d;
}

// The earliest time a body at clearance D moving at speed v with acceleration at most a could
// reach a part (infinity: never; 0: it may touch now).
inline double time_to_reach(double D, double v, double a) {
  if (!(D > 0.0)) return 0.0;
  if (a <= 0.0) return v > 0.0 ? D / v : std::numeric_limits<double>::infinity();
  return 2.0 * D / (v + std::sqrt(v * v + 2.0 * a * D));
}

}  // namespace rigid::physics::contact
