// The first instant at which a moving body touches a static part, found on the body's own
// trajectory over part of a step: the motion the integrator follows (exact free flight, or the
// scheme's own stage for a loaded body), evaluated at any time within it.
//
// Conservative advancement (Mirtich, "Impulse-based dynamic simulation of rigid body systems",
// PhD thesis, Berkeley 1996, ch. 3) with quadratic bounds: the gap is the minimum of a few smooth
// functions g_i(s) (a box's corners, a capsule's ends, a sphere's centre, ...), and each satisfies
//   g_i(s + d) >= g_i(s) + g_i'(s) d - C_i d^2 / 2
// with C_i bounding |g_i''| over the interval (from bounds on the body's acceleration, angular
// velocity and angular acceleration). Advancing by the smallest positive root of these bounds never
// passes a root of the gap, and near the root it is Newton's step on the gap: the search converges
// from outside, quadratically, to the touch itself, so that the body is never found inside the
// part and the time is exact to round-off (against a plane, where the gap is exact).
#pragma once

#include <cstdint>

#include "physics/contact/gap.hpp"
#include "physics/contact/static_part.hpp"
#include "physics/contact/support.hpp"

namespace rigid::physics::contact {

// A body's motion at one instant: pose and velocities (v of the centre of mass, w, both in W).
struct MotionSample {
  Pose pose;
  Vec3 v_W = Vec3::Zero();
  Vec3 w_W = Vec3::Zero();
};

// The motion over an interval [0, length] of a step, and bounds that hold over all of it.
class Trajectory {
 public:
  virtual ~Trajectory() = default;
  virtual MotionSample at(double s) const = 0;
  double length = 0.0;
  double a_max = 0.0;      // |dv/ds|
  double w_max = 0.0;      // |w|
  double alpha_max = 0.0;  // |dw/ds|
};

struct Touch {
  bool found = false;
  double s = 0.0;  // when (within the trajectory's interval)
  MotionSample at;
  Gap gap;
  int iterations = 0;
};

// The first s in [s_begin, trajectory.length] at which the body's gap to the part closes
// (to within round-off of its position), or found == false when it stays open. A body that starts
// touching the part and moving away from it (an impact just resolved) is found again only once it
// has left and comes back. `ignore`: pieces of the gap against a plane left out (bit k: piece k of
// plane_pieces), the ones a body rests on, so that only its other features are watched.
Touch first_touch(const Convex& body, const StaticPart& part, const Trajectory& trajectory,
                  double s_begin, std::uint32_t ignore = 0);

// The first s in [s_begin, min(ta.length, tb.length)] at which bodies a and b, each on its own
// trajectory over the same interval, touch; found == false when they stay apart. As first_touch,
// with the pair's gap (pair_gap.hpp) as the one piece: its rate that of the closest points'
// relative velocity along the normal, its curvature bounded by both bodies' accelerations and
// turns and by the relative speed squared over the distance between the closest features (a
// distance to a convex set bends no more than that). `at` holds a's state, `at_b` b's.
struct PairTouch {
  bool found = false;
  double s = 0.0;
  MotionSample at, at_b;
  int iterations = 0;
};
PairTouch first_touch_pair(const Convex& a, const Trajectory& ta, const Convex& b,
                           const Trajectory& tb, double s_begin);

// The pieces of a body's gap to a plane (the smooth functions whose minimum it is: a box's 8
// corners, a capsule's or a cylinder's 2 ends, a sphere's, a point's or an ellipsoid's one), and
// which of them rest on the plane in state m: within `tol` of it and moving away from it no faster
// than max_rate (bit k for piece k). A piece leaving faster is watched, to be found on its return.
int plane_pieces(const Convex& body);
std::uint32_t resting_pieces(const Convex& body, const MotionSample& m, const StaticPart& plane,
                             double tol, double max_rate);

// The gap below which a body counts as touching: round-off in a position of size `scale` (m).
inline double touch_tolerance(double scale) {
  return 1e-12 * (1.0 + scale);
}

}  // namespace rigid::physics::contact
