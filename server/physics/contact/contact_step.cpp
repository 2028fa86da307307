#include "physics/contact/contact_step.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "physics/contact/gap.hpp"
#include "physics/contact/point_solver.hpp"
#include "physics/contact/time_of_impact.hpp"

namespace rigid::physics::contact {

namespace {

// Points within this of a support's level belong to it (a face's corners after a landing agree
// to round-off; a face tilted by less than this over its size is taken as lying flat).
constexpr double kFeatureTol = 1e-9;
// Accelerations below this (m/s^2) are the round-off of forces that balance.
constexpr double kStillAccel = 1e-9;
// The most events one body's step is split at; beyond, the rest of the step is taken whole.
constexpr int kMaxRounds = 128;
// The largest angle (rad) a body turning on sharp supports turns in one sub-step.
constexpr double kMaxTurn = 0.01;

using Phase = SupportState::Phase;

// One contact point: where, its normal, the pair's surface, the part.
struct Point {
  Vec3 p_W, n_W;
  Surface surface;
  std::int32_t part;
};

struct Points {
  std::array<Point, kMaxPoints> at;
  int n = 0;
  // The parts touched, with the plane pieces each rests on.
  std::array<std::int32_t, kMaxPoints> parts{};
  std::array<std::uint32_t, kMaxPoints> pieces{};
  int n_parts = 0;
};

// Every point where the body touches a candidate part now, and per plane the pieces of its gap
// resting on it (not moving away).
Points touching(const ContactBody& cb, std::span<const StaticPart> parts, const MotionSample& m) {
  Points out;
  const Pose& pose = m.pose;
  const double tol = touch_tolerance(pose.p_WBo.norm());
  for (const std::int32_t k : cb.candidates) {
    const StaticPart& part = parts[k];
    const Gap g = gap(*cb.shape, pose, part);
    if (g.distance > std::max(tol, kFeatureTol)) continue;
    std::array<Vec3, kMaxFeature> pts;
    const int n = touching_points(*cb.shape, pose, part, g, kFeatureTol, pts);
    const Surface s = combine(cb.surface, part.surface);
    for (int i = 0; i < n && out.n < kMaxPoints; ++i)
      out.at[out.n++] = Point{pts[i], g.n_W, s, k};
    if (out.n_parts < kMaxPoints) {
      out.parts[out.n_parts] = k;
      out.pieces[out.n_parts] = part.kind == StaticPart::Kind::kPlane
                                    ? resting_pieces(*cb.shape, m, part, kFeatureTol, kStillSpeed)
                                    : ~0u;
      ++out.n_parts;
    }
  }
  return out;
}

// A body's points are material (a box's corners) or slide over its surface as it turns (the
// rounded and smooth shapes): the latter's contact does not feel the centripetal acceleration of
// a point fixed in the body (a rolling sphere's centre keeps its height however fast it spins).
bool sharp(const Convex& c) {
  return c.kind == Convex::Kind::kBox;
}

// The feature of the body a contact point belongs to, in B, from the point p_B and the direction
// u_B towards the part: a box's corner itself; the core point under a rounded shape's surface (a
// sphere's centre, a capsule's end); a cylinder's end centre. Followed through a sub-step, it gives
// the point that touches at each instant (contact_offset), rolling over the surface where it does.
Vec3 core_feature(const Convex& c, const Vec3& p_B, const Vec3& u_B) {
  switch (c.kind) {
    case Convex::Kind::kSphere:
    case Convex::Kind::kCapsule:
      return p_B - c.radius * u_B;
    case Convex::Kind::kCylinder:
      return Vec3(0.0, 0.0, p_B.z() < 0.0 ? -c.half.z() : c.half.z());
    default:
      return p_B;
  }
}
// Where that feature touches along the normal n at `pose`, from the centre of mass (W).
Vec3 contact_offset(const Convex& c, const Pose& pose, const Vec3& n, const Vec3& core_B,
                    const StaticPart& part) {
  switch (c.kind) {
    case Convex::Kind::kSphere:
    case Convex::Kind::kCapsule:
      return pose.q_WB * core_B - c.radius * n;
    case Convex::Kind::kCylinder: {
      const Vec3 u_B = pose.q_WB.conjugate() * (-n);
      const double t = std::hypot(u_B.x(), u_B.y());
      const Vec3 rim =
          t > 0.0 ? Vec3(c.half.x() * u_B.x() / t, c.half.x() * u_B.y() / t, 0.0) : Vec3::Zero();
      return pose.q_WB * (core_B + rim);
    }
    case Convex::Kind::kEllipsoid:
      return gap(c, pose, part).p_W - pose.p_WBo;
    default:
      return pose.q_WB * core_B;
  }
}

void emit(EventSink& sink, ContactEventKind kind, std::int32_t body, std::int32_t part, double t,
          const Vec3& p, const Vec3& n, const Vec3& J = Vec3::Zero()) {
  ContactEvent e;
  e.kind = kind;
  e.body = body;
  e.part = part;
  e.time = t;
  e.p_W = p;
  e.n_W = n;
  e.impulse_W = J;
  sink.push(e);
}

ContactEventKind event_of(Phase p) {
  switch (p) {
    case Phase::kResting:
      return ContactEventKind::kResting;
    case Phase::kSliding:
      return ContactEventKind::kSliding;
    case Phase::kRolling:
      return ContactEventKind::kRolling;
    case Phase::kFree:
      break;
  }
  return ContactEventKind::kSeparate;
}

class Stepper {
 public:
  Stepper(MovingBody& body, const ContactBody& cb, std::span<const StaticPart> parts,
          SupportState& st, EventSink& sink)
      : body_(body), cb_(cb), parts_(parts), st_(st), sink_(sink) {}

  ContactStepResult run(double dt) {
    ContactStepResult r;
    if (st_.phase == Phase::kResting && st_.settled) return r;
    const double e_start = body_.energy();
    double t = 0.0;
    for (; t < dt && r.rounds < kMaxRounds; ++r.rounds) {
      const double h = dt - t;
      if (st_.phase == Phase::kFree) {
        t += free_flight(t, h, nullptr);
      } else {
        t += supported(t, h);
      }
    }
    if (t < dt) {
      // Out of rounds (events accumulating faster than they can be resolved one by one): the
      // body holds its state over the rest of the step, which neither moves it into a part nor
      // gives it energy. Counted, so that it shows.
      r.capped = true;
    }
    keep_out();
    no_energy_gain(e_start);
    return r;
  }

 private:
  // Free flight until the first touch (or the end); returns the time taken. `left`: supports just
  // left, whose touching pieces are not watched this time.
  double free_flight(double t, double h, const Points* left = nullptr) {
    const Trajectory& tr = body_.plan(h, SupportLoad{});
    Touch best;
    for (const std::int32_t k : cb_.candidates) {
      std::uint32_t ignore = 0;
      for (int j = 0; left != nullptr && j < left->n_parts; ++j) {
        if (left->parts[j] == k) ignore = left->pieces[j];
      }
      if (ignore == ~0u) continue;
      const Touch touch = first_touch(*cb_.shape, parts_[k], tr, 0.0, ignore);
      if (touch.found && (!best.found || touch.s < best.s)) best = touch;
    }
    if (!best.found) {
      body_.advance(h);
      return h;
    }
    body_.advance(best.s);
    impact(t + best.s, h - best.s);
    return best.s;
  }

  // Solves the impulses at every touching point at time t; the body's phase follows from what
  // they leave. `left`: the rest of the step (for summing a bounce series within it).
  void impact(double t, double left) {
    const MotionSample m = body_.state();
    const Points pts = touching(cb_, parts_, m);
    if (pts.n == 0) return;  // grazed and gone
    const Response resp = body_.response();
    std::array<PointRow, kMaxPoints> rows;
    bool approaching = false;
    double e_max = 0.0, u_in = 0.0;
    for (int i = 0; i < pts.n; ++i) {
      const Point& p = pts.at[i];
      PointRow& row = rows[i];
      row.r_W = p.p_W - m.pose.p_WBo;
      row.n_W = p.n_W;
      row.mu = p.surface.friction;
      row.patch = p.part;
      row.u_W = m.v_W + m.w_W.cross(row.r_W);
      const double un = row.n_W.dot(row.u_W);
      row.target = un < 0.0 ? -p.surface.restitution * un : 0.0;
      if (un < -kStillSpeed) {
        approaching = true;
        e_max = std::max(e_max, p.surface.restitution);
        u_in = std::max(u_in, -un);
      }
    }
    if (!approaching) {
      // A touch at no normal speed: whether the part holds the body is the supports' question.
      st_.phase = Phase::kSliding;
      st_.settled = false;
      return;
    }
    const double e0 = body_.energy();
    PointSolution sol = solve_points(resp, rows.data(), pts.n, m.w_W);
    const auto rises = [&](const PointSolution& s) {
      return body_.conservative() && energy_after(m, s) > e0 + 1e-14 * std::abs(e0);
    };
    if (rises(sol)) {
      // Newton's law with friction can add energy at a coupled point (Kane and Levinson's
      // example); a perfectly plastic impact cannot: take it instead.
      for (int i = 0; i < pts.n; ++i)
        rows[i].target = 0.0;
      sol = solve_points(resp, rows.data(), pts.n, m.w_W);
      if (rises(sol)) {
        for (int i = 0; i < pts.n; ++i)
          rows[i].mu = 0.0;
        sol = solve_points(resp, rows.data(), pts.n, m.w_W);
      }
    }
    // The bounce that follows, if it would repeat within the step, summed: the body leaves at
    // u = min normal speed of the touching points (all alike for a face; one point otherwise),
    // and its normal acceleration brings it back after 2 u / g_n, each bounce e times shorter.
    // How fast the touching points leave: u_out the slowest (all alike for a face landing flat),
    // u_back the fastest of those that bounce.
    double u_out = std::numeric_limits<double>::infinity(), u_back = 0.0;
    for (int i = 0; i < pts.n; ++i) {
      const PointRow& row = rows[i];
      const double un = row.n_W.dot(row.u_W + sol.dv + sol.dw.cross(row.r_W));
      u_out = std::min(u_out, un);
      u_back = std::max(u_back, un);
    }
    // A bounce that would repeat within the step, summed: a point leaving at u under the normal
    // acceleration -g_n comes back after 2 u / g_n, each bounce e times shorter; the series takes
    // 2 u / (g_n (1 - e)) in all (exactly, for a body whose points all leave alike; for a corner
    // bouncing while the body turns on another, the same sum over its own speed, first order).
    bool summed = false;
    double series_end = t;
    if (u_back > kStillSpeed && e_max < 1.0) {
      Vec3 a, alpha;
      body_.free_accelerations(a, alpha);
      const double g_n = -pts.at[0].n_W.dot(a);
      if (g_n > 0.0) {
        const double total = 2.0 * u_back / (g_n * (1.0 - e_max));
        if (total <= left) {
          summed = true;
          series_end = t + total;
          for (int i = 0; i < pts.n; ++i)
            rows[i].target = 0.0;
          sol = solve_points(resp, rows.data(), pts.n, m.w_W);
          u_out = 0.0;
        }
      }
    }
    body_.set_velocity(m.v_W + sol.dv, m.w_W + sol.dw);
    // One event per part: the impulses' sum at their weighted centre.
    for (int k = 0; k < pts.n_parts; ++k) {
      Vec3 J = Vec3::Zero(), c = Vec3::Zero();
      double w = 0.0;
      for (int i = 0; i < pts.n; ++i) {
        if (pts.at[i].part != pts.parts[k]) continue;
        J += sol.P[i];
        const double pn = std::max(sol.P[i].dot(pts.at[i].n_W), 0.0);
        c += pn * pts.at[i].p_W;
        w += pn;
      }
      const Vec3& n = parts_normal(pts, k);
      emit(sink_, ContactEventKind::kImpact, cb_.id, pts.parts[k], t,
           w > 0.0 ? Vec3(c / w) : first_point(pts, k), n, J);
    }
    if (!summed && u_out > kStillSpeed) {
      st_.phase = Phase::kFree;  // bouncing
      return;
    }
    // Supported from here (for a summed series, from its end on: that is when it settles).
    pending_transition_ = summed ? series_end : t;
    st_.phase = Phase::kSliding;  // provisional: the supports decide
    st_.settled = false;
    announced_ = Phase::kFree;
  }

  // The body on its supports until the next event; returns the time taken.
  double supported(double t, double h_left) {
    double h = h_left;
    MotionSample m = body_.state();
    const Points pts = touching(cb_, parts_, m);
    if (pts.n == 0) {
      leave(t, m);
      return 0.0;
    }
    Vec3 a_free, alpha_free;
    body_.free_accelerations(a_free, alpha_free);
    // Each point's bounce speed: below it, a point leaving or closing in would bounce back within
    // the step, its bounces summing to a finite time (the series of impact()); such a point is a
    // support, its normal speed taken to zero. Faster, a point closing in is an impact and one
    // leaving is leaving.
    std::array<double, kMaxPoints> bounce{};
    for (int i = 0; i < pts.n; ++i) {
      const double g_n = -pts.at[i].n_W.dot(a_free);
      const double e = pts.at[i].surface.restitution;
      bounce[i] = std::max(kStillSpeed, g_n > 0.0 ? 0.5 * g_n * h * (1.0 - e) : 0.0);
      const Vec3 r = pts.at[i].p_W - m.pose.p_WBo;
      if (pts.at[i].n_W.dot(m.v_W + m.w_W.cross(r)) < -bounce[i]) {
        impact(t, h);
        return 0.0;
      }
    }
    const Response resp = body_.response();
    m = hold_still(m, pts, bounce, resp);
    std::array<PointRow, kMaxPoints> rows;
    std::array<bool, kMaxPoints> slipping{};
    std::array<Vec3, kMaxPoints> slip_now;  // each slipping point's slip direction now
    int n = 0;
    bool sliding = false;
    for (int i = 0; i < pts.n; ++i) {
      const Point& p = pts.at[i];
      PointRow& row = rows[n];
      row = PointRow{};
      row.r_W = p.p_W - m.pose.p_WBo;
      row.n_W = p.n_W;
      row.mu = p.surface.friction;
      row.patch = p.part;
      const Vec3 u = m.v_W + m.w_W.cross(row.r_W);
      // A point moving away from its part is leaving it: it carries no force.
      if (row.n_W.dot(u) > bounce[i]) continue;
      const Vec3 slip = u - row.n_W * row.n_W.dot(u);
      const double slip_speed = slip.norm();
      // A slip friction would stop within a millionth of the sub-step stops now: stop events
      // that close on each other at round-off (two points of a line taking turns) would
      // otherwise split the step without end, for a time error of at most 1e-6 h.
      const double slip_floor =
          std::max(kStillSpeed, 1e-6 * h * row.mu * std::abs(row.n_W.dot(a_free)));
      slipping[n] = slip_speed > slip_floor && row.mu > 0.0;
      if (slipping[n]) {
        row.sliding = true;
        row.slip_W = slip / slip_speed;
        slip_now[n] = row.slip_W;
        sliding = true;
      }
      row.u_W = a_free + alpha_free.cross(row.r_W);
      if (sharp(*cb_.shape)) row.u_W += m.w_W.cross(m.w_W.cross(row.r_W));
      row.target = 0.0;
      part_of_[n] = p.part;
      ++n;
    }
    if (n == 0) {
      // Every point is leaving its part: free flight, watching them come back.
      leave(t, m);
      return free_flight(t, h_left, nullptr);
    }
    // A sliding point whose friction would pull it into its part as the normal force grows (a
    // Painleve configuration: no force satisfies the laws) stops slipping at once instead, by a
    // tangential impact: a plastic impulse that sticks it if the friction cone allows.
    for (int i = 0; i < n; ++i) {
      if (!rows[i].sliding) continue;
      const Vec3 d = rows[i].n_W - rows[i].mu * rows[i].slip_W;
      if (rows[i].n_W.dot(resp.K(rows[i].r_W, rows[i].r_W) * d) > 0.0) continue;
      std::array<PointRow, kMaxPoints> stop;
      for (int j = 0; j < n; ++j) {
        stop[j] = rows[j];
        stop[j].sliding = false;
        stop[j].target = 0.0;
        stop[j].u_W = m.v_W + m.w_W.cross(rows[j].r_W);
      }
      const PointSolution jolt = solve_points(resp, stop.data(), n, m.w_W);
      body_.set_velocity(m.v_W + jolt.dv, m.w_W + jolt.dw);
      emit(sink_, ContactEventKind::kImpact, cb_.id, part_of_[i], t, pts.at[0].p_W, rows[i].n_W,
           jolt.F);
      return 0.0;
    }
    // Sliding friction's direction, taken implicitly: where the slip will point at the end of the
    // sub-step under the other forces, u_t + h a_t (backward Euler on the slip, after the
    // frictionless solve gives a_t). Held along the slip it has now, friction would overshoot a
    // sideways slip that it damps at a rate mu g / |u| (stiff for a slow slide) and turn it into a
    // growing zigzag; along the end slip it only ever shrinks it. For a slip that keeps its line
    // (the closed-form cases) the two agree; for one that stops within the sub-step, the current
    // direction holds until the stop, which an event finds.
    if (sliding) {
      std::array<PointRow, kMaxPoints> plain = rows;
      for (int i = 0; i < n; ++i) {
        plain[i].mu = 0.0;
        plain[i].sliding = false;
      }
      const PointSolution normal_only = solve_points(resp, plain.data(), n, alpha_free);
      for (int i = 0; i < n; ++i) {
        if (!slipping[i]) continue;
        const Vec3& nrm = rows[i].n_W;
        const Vec3 acc = rows[i].u_W + normal_only.dv + normal_only.dw.cross(rows[i].r_W);
        const Vec3 u = m.v_W + m.w_W.cross(rows[i].r_W);
        const Vec3 u_t = u - nrm * nrm.dot(u);
        const Vec3 end = u_t + h * (acc - nrm * nrm.dot(acc));
        if (end.dot(u_t) > 0.0) rows[i].slip_W = end.normalized();
      }
    }
    PointSolution sol = solve_points(resp, rows.data(), n, alpha_free);
    // A sticking point whose friction reached its limit slips, the way it would accelerate with
    // that friction: solved again with it sliding so (Coulomb's law at the onset of slip).
    for (int pass = 0; pass < 3; ++pass) {
      bool changed = false;
      for (int i = 0; i < n; ++i) {
        if (!sol.saturated[i]) continue;
        const Vec3 acc = rows[i].u_W + sol.dv + sol.dw.cross(rows[i].r_W);
        const Vec3 tang = acc - rows[i].n_W * rows[i].n_W.dot(acc);
        if (tang.norm() <= kStillAccel) continue;
        rows[i].sliding = true;
        rows[i].slip_W = tang.normalized();
        changed = sliding = true;
      }
      if (!changed) break;
      sol = solve_points(resp, rows.data(), n, alpha_free);
    }
    SupportLoad load{sol.F, sol.tau};
    bool pushed = false;
    for (int i = 0; i < n; ++i)
      pushed = pushed || sol.P[i].dot(rows[i].n_W) > 0.0;
    if (!pushed) {
      // Nothing presses it on its supports: it leaves them, and flies on without finding at once
      // the features it left (they graze the part with no speed towards it).
      leave(t, m);
      return free_flight(t, h_left, &pts);
    }
    const double rho = cb_.shape->bounding_radius();
    const Vec3 a = a_free + sol.dv, alpha = alpha_free + sol.dw;
    const bool still = m.v_W.norm() <= kStillSpeed && m.w_W.norm() * rho <= kStillSpeed;
    if (!sliding && still && a.norm() <= kStillAccel && alpha.norm() * rho <= kStillAccel) {
      body_.set_velocity(Vec3::Zero(), Vec3::Zero());
      announce(Phase::kResting, t, pts, m.pose);
      st_.settled = true;
      return h;  // nothing moves for the rest of the step
    }
    announce(sliding ? Phase::kSliding : Phase::kRolling, t, pts, m.pose);
    hold_ = load;
    // A sliding face turning about its normal: friction damps the turn, stiffly when the slip is
    // slow (the damping rate grows as 1/slip), and forces held over a sub-step longer than the
    // damping time would overshoot. The sub-step ends where the turn would stop, and no later than
    // where it would turn a point's slip by a sizeable angle; at most kMaxRounds of them a step.
    if (sliding && n > 1) {
      const Vec3& nrm = rows[0].n_W;
      const double w_n = nrm.dot(m.w_W), a_n = nrm.dot(alpha);
      // The slip of the face as a whole: at the centre of its points.
      Vec3 c = Vec3::Zero();
      for (int i = 0; i < n; ++i)
        c += rows[i].r_W / n;
      const Vec3 u = m.v_W + m.w_W.cross(c);
      const double slip = (u - nrm * nrm.dot(u)).norm();
      // (Turns and turning rates at round-off are no turn.)
      const bool turning = std::abs(w_n) * rho > kStillSpeed;
      const bool braked = std::abs(a_n) * rho > kStillAccel;
      if (turning && braked && w_n * a_n < 0.0) h = std::min(h, -w_n / a_n);
      if (braked && slip > kStillSpeed) h = std::min(h, 0.5 * slip / (std::abs(a_n) * rho));
    }
    // A body turning on sharp supports (a box on an edge or a corner) is held by forces that turn
    // with it: held constant, they are right to first order in the angle turned, so a sub-step
    // turns it by at most kMaxTurn across the normal.
    if (sharp(*cb_.shape)) {
      const Vec3& nrm = rows[0].n_W;
      const double w_t = (m.w_W - nrm * nrm.dot(m.w_W)).norm();
      const double a_t = (alpha - nrm * nrm.dot(alpha)).norm();
      const double turn = w_t * h + 0.5 * a_t * h * h;
      if (turn > kMaxTurn) {
        // The h at which w_t h + a_t h^2 / 2 = kMaxTurn.
        h = a_t > 0.0 ? 2.0 * kMaxTurn / (w_t + std::sqrt(w_t * w_t + 2.0 * a_t * kMaxTurn))
                      : kMaxTurn / w_t;
      }
    }
    const Trajectory& tr = body_.plan(h, load);
    double s_event = h;
    // Slips that stop: the first s where a sliding point's slip no longer points the way it did.
    for (int i = 0; i < n; ++i) {
      // A slip that starts now grows over the sub-step: only one under way can stop.
      if (!rows[i].sliding || !slipping[i]) continue;
      const Vec3 core_B = core_feature(*cb_.shape, m.pose.q_WB.conjugate() * rows[i].r_W,
                                       m.pose.q_WB.conjugate() * (-rows[i].n_W));
      const auto along = [&](double s) {
        const MotionSample q = tr.at(s);
        const Vec3 r = contact_offset(*cb_.shape, q.pose, rows[i].n_W, core_B, parts_[part_of_[i]]);
        const Vec3 u = q.v_W + q.w_W.cross(r);
        return slip_now[i].dot(u - rows[i].n_W * rows[i].n_W.dot(u));
      };
      const double stop = first_root(along, 0.0, along(0.0), s_event);
      s_event = std::min(s_event, stop);
    }
    // Other features and parts touched on the way.
    for (const std::int32_t k : cb_.candidates) {
      std::uint32_t ignore = 0;
      bool supporting = false;
      for (int j = 0; j < pts.n_parts; ++j) {
        if (pts.parts[j] == k) supporting = true, ignore = pts.pieces[j];
      }
      if (supporting && parts_[k].kind != StaticPart::Kind::kPlane) continue;
      const Touch touch = first_touch(*cb_.shape, parts_[k], tr, 0.0, ignore);
      if (touch.found && touch.s < s_event) s_event = touch.s;
    }
    const double e0 = body_.energy();
    body_.advance(s_event);
    settle_drift(pts, e0);
    return s_event;
  }

  // A support's normal speed is zero: the forces below hold its acceleration there, and a speed
  // left in it (round-off in a face tipping at 1e-15 rad/s, or a corner's bounces that sum within
  // the step) would grow unchecked or repeat without end. The normal speeds below each point's
  // bounce speed are taken to zero by a frictionless plastic impulse (which only takes energy
  // away); a point leaving faster is leaving.
  MotionSample hold_still(const MotionSample& m, const Points& pts,
                          const std::array<double, kMaxPoints>& bounce, const Response& resp) {
    std::array<PointRow, kMaxPoints> rows;
    int n = 0;
    bool moving = false;
    for (int i = 0; i < pts.n; ++i) {
      PointRow& row = rows[n];
      row = PointRow{};
      row.r_W = pts.at[i].p_W - m.pose.p_WBo;
      row.n_W = pts.at[i].n_W;
      row.u_W = m.v_W + m.w_W.cross(row.r_W);
      const double un = row.n_W.dot(row.u_W);
      if (std::abs(un) > bounce[i]) continue;
      moving = moving || un != 0.0;
      ++n;
    }
    MotionSample out = m;
    // A face (two points or more) turning about its normal at round-off speed is not turning.
    if (n > 1) {
      const Vec3& nrm = rows[0].n_W;
      const double w_n = nrm.dot(out.w_W);
      if (w_n != 0.0 && std::abs(w_n) * cb_.shape->bounding_radius() <= kStillSpeed) {
        out.w_W -= w_n * nrm;
        body_.set_velocity(out.v_W, out.w_W);
        for (int i = 0; i < n; ++i)
          rows[i].u_W = out.v_W + out.w_W.cross(rows[i].r_W);
      }
    }
    if (!moving) return out;
    const PointSolution sol = solve_points(resp, rows.data(), n, out.w_W);
    out.v_W += sol.dv;
    out.w_W += sol.dw;
    body_.set_velocity(out.v_W, out.w_W);
    return out;
  }

  // The step ends with the body outside every part: a capped step, or a feature a support let go
  // of that came back unwatched, would otherwise leave it inside. Moved out along the normal, its
  // speed into the part taken away (a plastic touch).
  void keep_out() {
    for (const std::int32_t k : cb_.candidates) {
      const MotionSample m = body_.state();
      const Gap g = gap(*cb_.shape, m.pose, parts_[k]);
      // Inside by round-off of its position at most: left as it is (a lift would give it
      // potential energy that nothing pays for).
      if (g.distance >= -touch_tolerance(m.pose.p_WBo.norm())) continue;
      body_.shift(-g.distance * g.n_W);
      const Vec3 r = g.p_W - m.pose.p_WBo;
      const double un = g.n_W.dot(m.v_W + m.w_W.cross(r));
      if (un >= 0.0) continue;
      PointRow row;
      row.r_W = r;
      row.n_W = g.n_W;
      row.u_W = m.v_W + m.w_W.cross(r);
      const PointSolution sol = solve_points(body_.response(), &row, 1, m.w_W);
      body_.set_velocity(m.v_W + sol.dv, m.w_W + sol.dw);
    }
  }

  // A body under gravity alone ends no step with more energy than it began it with: the forces
  // held over sub-steps of a turning body and the moves out of the parts can work on it a little,
  // and the excess is taken from its kinetic energy (what is left of it, if it is less).
  void no_energy_gain(double e_start) {
    if (!body_.conservative()) return;
    const double excess = body_.energy() - e_start;
    if (!(excess > 0.0)) return;
    const double ke = body_.kinetic_energy();
    if (ke <= 0.0) return;
    const MotionSample m = body_.state();
    const double scale = std::sqrt(std::max(0.0, 1.0 - excess / ke));
    body_.set_velocity(scale * m.v_W, scale * m.w_W);
  }

  // The supports' drift over a sub-step of a turning body taken back: a point found inside its
  // part moves the body out along the normal; and the energy of a body under gravity alone may
  // not have risen (forces held over the sub-step work a little on a turning body).
  void settle_drift(const Points& before, double e0) {
    const MotionSample m = body_.state();
    for (int j = 0; j < before.n_parts; ++j) {
      const StaticPart& part = parts_[before.parts[j]];
      const Gap g = gap(*cb_.shape, m.pose, part);
      if (g.distance < -touch_tolerance(m.pose.p_WBo.norm())) body_.shift(-g.distance * g.n_W);
    }
    if (!body_.conservative()) return;
    const double e1 = body_.energy();
    if (e1 <= e0) return;
    // Take the excess out of the kinetic energy (never below zero).
    const MotionSample now = body_.state();
    const double ke = body_.kinetic_energy();
    if (ke <= 0.0) return;
    const double scale = std::sqrt(std::max(0.0, 1.0 - (e1 - e0) / ke));
    body_.set_velocity(scale * now.v_W, scale * now.w_W);
  }

  // The kinetic energy after an impulse solution, as energy() will count it.
  double energy_after(const MotionSample& m, const PointSolution& s) {
    const Vec3 v = m.v_W + s.dv, w = m.w_W + s.dw;
    body_.set_velocity(v, w);
    const double e = body_.energy();
    body_.set_velocity(m.v_W, m.w_W);
    return e;
  }

  void leave(double t, const MotionSample& m) {
    if (st_.phase != Phase::kFree) {
      emit(sink_, ContactEventKind::kSeparate, cb_.id, -1, t, m.pose.p_WBo, Vec3::Zero());
    }
    st_.phase = Phase::kFree;
    st_.settled = false;
    announced_ = Phase::kFree;
  }

  void announce(Phase p, double t, const Points& pts, const Pose& pose) {
    if (p != announced_) {
      const double when = std::max(t, pending_transition_);
      // The event names the first support and the centre of the points on it.
      emit(sink_, event_of(p), cb_.id, pts.parts[0], when, centre(pts, 0), pts.at[0].n_W);
      announced_ = p;
    }
    (void)pose;
    if (st_.phase != p) st_.phase = p;
  }

  static Vec3 centre(const Points& pts, int k) {
    Vec3 c = Vec3::Zero();
    int n = 0;
    for (int i = 0; i < pts.n; ++i) {
      if (pts.at[i].part == pts.parts[k]) c += pts.at[i].p_W, ++n;
    }
    return n > 0 ? Vec3(c / n) : Vec3::Zero();
  }
  static Vec3 first_point(const Points& pts, int k) { return centre(pts, k); }
  static const Vec3& parts_normal(const Points& pts, int k) {
    for (int i = 0; i < pts.n; ++i) {
      if (pts.at[i].part == pts.parts[k]) return pts.at[i].n_W;
    }
    return pts.at[0].n_W;
  }

  // The first s in (0, end] where f, positive at 0 (f0), reaches zero, or end when f(end) > 0 (a
  // slip under forces held constant changes monotonically): a scan brackets the first sign change,
  // then the Illinois method (regula falsi that halves a stuck end's weight: Dowell & Jarratt,
  // BIT 11, 1971) converges on it.
  template <class F>
  static double first_root(F&& f, double a, double fa, double end) {
    if (fa <= 0.0) return a;
    double hi = end, fhi = f(end);
    if (fhi > 0.0) return end;
    double lo = a, flo = fa;
    constexpr int kScan = 8;
    for (int k = 1; k < kScan; ++k) {
      const double s = a + (end - a) * k / kScan;
      const double fs = f(s);
      if (fs <= 0.0) {
        hi = s, fhi = fs;
        break;
      }
      lo = s, flo = fs;
    }
    int side = 0;
    for (int it = 0; it < 100 && hi - lo > 4 * std::numeric_limits<double>::epsilon() * hi; ++it) {
      const double s = (lo * fhi - hi * flo) / (fhi - flo);
      if (!(s > lo && s < hi)) break;
      const double fs = f(s);
      if (fs > 0.0) {
        lo = s, flo = fs;
        if (side == 1) fhi *= 0.5;
        side = 1;
      } else {
        hi = s, fhi = fs;
        if (side == -1) flo *= 0.5;
        side = -1;
      }
      if (fs == 0.0) return s;
    }
    return hi;
  }

  MovingBody& body_;
  const ContactBody& cb_;
  std::span<const StaticPart> parts_;
  SupportState& st_;
  EventSink& sink_;
  SupportLoad hold_;
  std::array<std::int32_t, kMaxPoints> part_of_{};  // the part of each supporting row
  Phase announced_ = Phase::kFree;
  double pending_transition_ = 0.0;

 public:
  void start() { announced_ = st_.phase; }
};

}  // namespace

}  // namespace rigid::physics::contact

namespace rigid::physics {

std::string_view to_string(ContactEventKind k) {
  switch (k) {
    case ContactEventKind::kImpact:
      return "impact";
    case ContactEventKind::kResting:
      return "resting";
    case ContactEventKind::kSliding:
      return "sliding";
    case ContactEventKind::kRolling:
      return "rolling";
    case ContactEventKind::kSeparate:
      return "separate";
  }
  return "?";
}

}  // namespace rigid::physics

namespace rigid::physics::contact {

ContactStepResult contact_step(MovingBody& body, const ContactBody& cb,
                               std::span<const StaticPart> parts, double dt, SupportState& st,
                               EventSink& events) {
  Stepper s(body, cb, parts, st, events);
  s.start();
  return s.run(dt);
}

}  // namespace rigid::physics::contact
