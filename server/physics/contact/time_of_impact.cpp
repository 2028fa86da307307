#include "physics/contact/time_of_impact.hpp"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <limits>

#include "physics/contact/pair_gap.hpp"

namespace rigid::physics::contact {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// The smallest d > 0 with g + r d - c d^2 / 2 = 0 (c >= 0): how far a function with value g, rate
// r and |second derivative| <= c is sure to stay positive. Written without cancellation.
double safe_step(double g, double r, double c) {
  if (g <= 0.0) {
    // Touching: it stays apart only while it moves away (or, with nothing to bend its path,
    // while it does not move closer).
    if (r < 0.0 || (r == 0.0 && c > 0.0)) return 0.0;
    return c > 0.0 ? 2.0 * r / c : kInf;
  }
  if (c == 0.0) return r < 0.0 ? g / -r : kInf;
  const double root = std::sqrt(r * r + 2.0 * c * g);
  return r < 0.0 ? 2.0 * g / (root - r) : (r + root) / c;
}

// One smooth piece of a gap: its value, rate and bound on its second derivative.
struct Piece {
  double g = kInf, r = 0.0, c = 0.0;
  // The gap's own rate now, where r is a pessimistic bound on it (a cylinder's rim): what says
  // whether the piece is closing in.
  double now = std::numeric_limits<double>::quiet_NaN();
  double rate_now() const { return std::isnan(now) ? r : now; }
  // How far the bound holds (a piece whose bound is valid only near the sample).
  double cap = kInf;
};

// The lower envelope of the pieces: the gap, the smallest safe step, and the rate of the lowest
// piece (the touching one).
struct Envelope {
  double gap = kInf;
  double rate = 0.0;
  double step = kInf;
  std::uint32_t ignore = 0;
  int next = 0;  // the index of the next piece added
  void add(const Piece& p) {
    if ((ignore >> next++) & 1u) return;
    if (p.g < gap) gap = p.g, rate = p.rate_now();
    step = std::min({step, safe_step(p.g, p.r, p.c), p.cap});
  }
};

// A material point c_B of the body (from the centre of mass, in B) with rounding `radius`, against
// the plane: its gap, rate, and the bound on its second derivative (|a + alpha x r + w x w x r|).
Piece plane_point(const MotionSample& m, const Trajectory& t, const StaticPart& plane,
                  const Vec3& c_B, double radius) {
  const Vec3 r_W = m.pose.q_WB * c_B;
  const Vec3& n = plane.n_W;
  Piece p;
  p.g = n.dot(m.pose.p_WBo + r_W) - radius - plane.offset;
  p.r = n.dot(m.v_W + m.w_W.cross(r_W));
  p.c = t.a_max + c_B.norm() * (t.alpha_max + t.w_max * t.w_max);
  return p;
}

Envelope plane_envelope(const Convex& body, const MotionSample& m, const Trajectory& t,
                        const StaticPart& plane, std::uint32_t ignore) {
  Envelope e;
  e.ignore = ignore;
  switch (body.kind) {
    case Convex::Kind::kPoint:
    case Convex::Kind::kSphere:
      e.add(plane_point(m, t, plane, Vec3::Zero(), body.radius));
      break;
    case Convex::Kind::kBox:
      for (int k = 0; k < 8; ++k) {
        const Vec3 c((k & 1 ? -1.0 : 1.0) * body.half.x(), (k & 2 ? -1.0 : 1.0) * body.half.y(),
                     (k & 4 ? -1.0 : 1.0) * body.half.z());
        e.add(plane_point(m, t, plane, c, 0.0));
      }
      break;
    case Convex::Kind::kCapsule:
      for (const double z : {body.half.z(), -body.half.z()})
        e.add(plane_point(m, t, plane, Vec3(0.0, 0.0, z), body.radius));
      break;
    case Convex::Kind::kCylinder: {
      // Each end's rim: its centre as a material point, less r |u_xy| (u: the plane's inward
      // normal in B), whose rate is at most r |w|: a lower bound of the rim's gap that is exact at
      // the sample and whose rate is pessimistic by at most r |w|.
      const Vec3 u_B = m.pose.q_WB.conjugate() * (-plane.n_W);
      const double r = body.half.x();
      const double t_xy = std::hypot(u_B.x(), u_B.y());
      const double lift = r * t_xy;
      // The rim's lowest point now (the disk's centre when it lies flat), for the rate now.
      const Vec3 rim =
          t_xy > 0.0 ? Vec3(r * u_B.x() / t_xy, r * u_B.y() / t_xy, 0.0) : Vec3::Zero();
      for (const double z : {body.half.z(), -body.half.z()}) {
        Piece p = plane_point(m, t, plane, Vec3(0.0, 0.0, z), 0.0);
        p.g -= lift;
        p.now = plane.n_W.dot(m.v_W + m.w_W.cross(m.pose.q_WB * (rim + Vec3(0.0, 0.0, z))));
        if (t_xy > 0.2) {
          // Tilted well off its end: the rim's lowest point moves smoothly round the rim, and
          // the gap's rate is that point's; its second derivative adds the rim's curvature term
          // r |u'|^2 / |u_xy| <= r w^2 / (t_xy / 2), while |u_xy| stays above half of what it
          // is, which it does for t_xy / (2 w) at least.
          p.r = p.now;
          p.c += r * t.w_max * t.w_max / (0.5 * t_xy);
          if (t.w_max > 0.0) p.cap = 0.5 * t_xy / t.w_max;
        } else {
          p.r -= r * t.w_max;
        }
        e.add(p);
      }
      break;
    }
    case Convex::Kind::kEllipsoid: {
      // Smooth and strictly convex: the support point slides over the surface, and the gap's
      // rate is that of the material point there (the envelope theorem). Its second derivative:
      // the material point's, plus h's curvature, |A^2 / |A u|| <= a_max^2 / a_min, times |u'|^2.
      const Gap g = plane_gap(body, m.pose, plane);
      const Vec3 r_W = g.p_W - m.pose.p_WBo;
      Piece p;
      p.g = g.distance;
      p.r = plane.n_W.dot(m.v_W + m.w_W.cross(r_W));
      const double a_big = body.half.maxCoeff(), a_small = body.half.minCoeff();
      p.c = t.a_max + a_big * (t.alpha_max + t.w_max * t.w_max) +
            a_big * a_big / a_small * t.w_max * t.w_max;
      e.add(p);
      break;
    }
  }
  return e;
}

Envelope shape_envelope(const Convex& body, const MotionSample& m, const Trajectory& t,
                        const StaticPart& part) {
  const Gap g = shape_gap(body, m.pose, part);
  const Vec3 r_W = g.p_W - m.pose.p_WBo;
  Piece p;
  p.g = g.distance;
  p.r = g.n_W.dot(m.v_W + m.w_W.cross(r_W));
  // The distance to a convex set bends by at most |v|^2 / d (its level sets are at least d round).
  const double rho = body.bounding_radius();
  const double v = m.v_W.norm() + t.a_max * t.length + t.w_max * rho;
  p.c = t.a_max + rho * (t.alpha_max + t.w_max * t.w_max) +
        v * v / std::max(g.distance, touch_tolerance(m.pose.p_WBo.norm()));
  Envelope e;
  e.add(p);
  return e;
}

}  // namespace

int plane_pieces(const Convex& body) {
  switch (body.kind) {
    case Convex::Kind::kBox:
      return 8;
    case Convex::Kind::kCapsule:
    case Convex::Kind::kCylinder:
      return 2;
    default:
      return 1;
  }
}

std::uint32_t resting_pieces(const Convex& body, const MotionSample& m, const StaticPart& plane,
                             double tol, double max_rate) {
  // The pieces' gaps and rates in state m (the bounds play no part).
  struct Still : Trajectory {
    MotionSample at(double) const override { return MotionSample{}; }
  } still;
  std::uint32_t mask = 0;
  const int n = plane_pieces(body);
  for (int k = 0; k < n; ++k) {
    const Envelope e = plane_envelope(body, m, still, plane, ~(1u << k));
    if (e.gap <= tol && e.rate <= max_rate) mask |= 1u << k;
  }
  return mask;
}

Touch first_touch(const Convex& body, const StaticPart& part, const Trajectory& trajectory,
                  double s_begin, std::uint32_t ignore) {
  constexpr int kMaxIterations = 200;
  Touch out;
  double s = s_begin;
  // The last sample found apart: where the touch is placed when round-off makes the final one
  // cross into the part by an ulp, so that a touch is never reported inside.
  double s_apart = -1.0;
  for (int it = 0; it < kMaxIterations; ++it) {
    out.iterations = it + 1;
    const MotionSample m = trajectory.at(s);
    const Envelope e = part.kind == StaticPart::Kind::kPlane
                           ? plane_envelope(body, m, trajectory, part, ignore)
                           : shape_envelope(body, m, trajectory, part);
    const double tol = touch_tolerance(m.pose.p_WBo.norm());
    // Touching: closing in with the gap within round-off of the position and the next safe step
    // no longer moving s (the search has reached the root from outside), or stalled on a grazing
    // touch, where the rate vanishes with the gap and the steps shrink to nothing.
    const bool no_progress = s + e.step == s || e.step <= 1e-15 * (1.0 + s);
    const bool closing = e.gap <= tol && e.rate < 0.0 && (no_progress || e.gap <= 1e-3 * tol);
    const bool stalled = no_progress && e.gap <= 1e3 * tol;
    if (closing || stalled) {
      out.found = true;
      out.s = s;
      out.at = m;
      out.gap = gap(body, m.pose, part);
      // Round-off may leave the last sample an ulp inside: back off towards the last sample
      // found apart (at most to it) until it is not.
      for (int k = 0; k < 8 && out.gap.distance < 0.0 && s_apart >= 0.0; ++k) {
        const double back = std::max(2.0 * -out.gap.distance / std::max(-e.rate, 1e-300),
                                     4.0 * std::numeric_limits<double>::epsilon() * out.s);
        out.s = std::max(s_apart, out.s - back);
        out.at = trajectory.at(out.s);
        out.gap = gap(body, out.at.pose, part);
      }
      return out;
    }
    if (e.gap > 0.0) s_apart = s;
    if (e.gap == kInf || s + e.step >= trajectory.length) return out;  // apart to the end
    s += e.step;
  }
  // Out of iterations while still apart: slow approach by a grazing body; it is not inside.
  return out;
}

PairTouch first_touch_pair(const Convex& a, const Trajectory& ta, const Convex& b,
                           const Trajectory& tb, double s_begin) {
  constexpr int kMaxIterations = 200;
  PairTouch out;
  const double length = std::min(ta.length, tb.length);
  const double rho_a = a.bounding_radius() - a.radius, rho_b = b.bounding_radius() - b.radius;
  const bool spheres = (a.kind == Convex::Kind::kPoint || a.kind == Convex::Kind::kSphere) &&
                       (b.kind == Convex::Kind::kPoint || b.kind == Convex::Kind::kSphere);
  double s = s_begin, s_apart = -1.0;
  for (int it = 0; it < kMaxIterations; ++it) {
    out.iterations = it + 1;
    const MotionSample ma = ta.at(s), mb = tb.at(s);
    const PairGap g = pair_gap(a, ma.pose, b, mb.pose);
    const Vec3 ua = ma.v_W + ma.w_W.cross(g.p_a_W - ma.pose.p_WBo);
    const Vec3 ub = mb.v_W + mb.w_W.cross(g.p_b_W - mb.pose.p_WBo);
    const double rate = g.n_W.dot(ua - ub);
    const double v = (ma.v_W - mb.v_W).norm() + (ta.a_max + tb.a_max) * (length - s) +
                     ta.w_max * (rho_a + a.radius) + tb.w_max * (rho_b + b.radius);
    const double tol = touch_tolerance(std::max(ma.pose.p_WBo.norm(), mb.pose.p_WBo.norm()));
    // The distance between the centres (spheres) or the closest features bends by v^2 / d.
    const double bend = spheres ? g.distance + a.radius + b.radius : std::max(g.distance, tol);
    const double c = ta.a_max + tb.a_max + rho_a * (ta.alpha_max + ta.w_max * ta.w_max) +
                     rho_b * (tb.alpha_max + tb.w_max * tb.w_max) + v * v / std::max(bend, tol);
    const double step = safe_step(g.distance, rate, c);
    const bool no_progress = s + step == s || step <= 1e-15 * (1.0 + s);
    const bool closing =
        g.distance <= tol && rate < 0.0 && (no_progress || g.distance <= 1e-3 * tol);
    const bool stalled = no_progress && g.distance <= 1e3 * tol;
    if (closing || stalled) {
      out.found = true;
      out.s = s;
      out.at = ma;
      out.at_b = mb;
      if (g.distance < 0.0 && s_apart >= 0.0) {
        out.s = s_apart;
        out.at = ta.at(s_apart);
        out.at_b = tb.at(s_apart);
      }
      return out;
    }
    if (g.distance > 0.0) s_apart = s;
    if (s + step >= length) return out;
    s += step;
  }
  return out;
}

}  // namespace rigid::physics::contact
