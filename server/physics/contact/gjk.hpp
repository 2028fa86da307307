// The distance between two convex cores and their closest points, by the
// Gilbert-Johnson-Keerthi algorithm (Gilbert, Johnson & Keerthi, IEEE J. Robotics and Automation
// 4(2), 1988) on the Minkowski difference A - B, with the closest point of each simplex found by
// its Voronoi regions (Ericson, "Real-Time Collision Detection", 2005, 5.1.2-5.1.6).
//
// The contact code keeps shapes apart (every impact is located before it happens), so the cores
// it asks about are disjoint or touching: there is no penetration depth to compute.
#pragma once

#include "physics/contact/support.hpp"
#include "physics/math.hpp"

namespace rigid::physics::contact {

// A convex shape placed in the world: its frame's origin and orientation.
struct Placed {
  const Convex* shape;
  Vec3 p_W;
  Quat q_W;
  // The core's support point along u_W, in W.
  Vec3 support_W(const Vec3& u_W) const {
    return p_W + q_W * shape->core_support(q_W.conjugate() * u_W);
  }
};

struct CoreDistance {
  double distance = 0.0;                        // between the cores (>= 0)
  Vec3 p_A = Vec3::Zero(), p_B = Vec3::Zero();  // closest points of the cores, in W
  int iterations = 0;
};

// Distance of the cores of a and b. Stops when the gap between GJK's upper and lower bounds is
// below rel_tol of the distance (exact at once for polytopes; smooth cores converge to it).
CoreDistance core_distance(const Placed& a, const Placed& b, double rel_tol = 1e-14);

}  // namespace rigid::physics::contact
