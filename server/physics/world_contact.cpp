// The World's contact stage (world.hpp's pipeline): which bodies it looks at each step, each one's
// motion over a step with contacts (contact/contact_step.hpp) over the World's own bodies, and
// how a body at rest is held at a free body's cost.
//
// Only a world with static parts has a contact stage. In it, a body is looked at in a step when
// it could touch a part within that step (its clearance and bounds on its speed and acceleration
// say when: contact/reach.hpp), or when parts support it. A free body looked at is first checked
// on its own trajectory over the step: if it touches nothing, the kernel's state stands, bit for
// bit what a world without parts computes; if it does, its step is taken again from its start by
// the contact stage, split at every event. A body that comes to rest with nothing turning it is
// held: its entry points at the still body's translation row, so that the kernels leave it exactly
// where it is, and the stage skips it until its loads, state or momentum change.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>

#include "physics/contact/contact_step.hpp"
#include "physics/contact/reach.hpp"
#include "physics/contact/time_of_impact.hpp"
#include "physics/free_rotor.hpp"
#include "physics/kernels.hpp"
#include "physics/translation.hpp"
#include "physics/world_impl.hpp"

namespace rigid::physics {

using detail::ConstGroup;
using detail::GroupTraits;
using detail::Linear;
using detail::Loads;
using detail::Motion;

namespace {

// --- one body's motion over part of a step ---

// The body's motion as the integrators' exact family takes it over a sub-step s from its state at
// the sub-step's start: a body nothing turns (its loads quiet) in free flight exactly (the drag
// flow under its constant acceleration, and the exact free rotor); a loaded one by Yoshida's
// triple jump of kick-drift-kick with exact drifts (fourth order, model.hpp: TripleJump).
template <BodyMotion K>
class BodyPath final : public contact::Trajectory {
 public:
  using Traits = GroupTraits<K>;
  using Rot = typename Traits::Rot;

  void plan(const Motion& start, const Linear& lin, const Rot& rot, const RotorInertia* rotor,
            const Quat& q_BP, const Loads& loads, double len) {
    start_ = start;
    lin_ = lin;
    rot_ = rot;
    rotor_ = rotor;
    q_BP_ = q_BP;
    loads_ = loads;
    quiet_ = loads.quiet();
    length = len;
    // Bounds over the sub-step. Force: its largest size at any orientation; acceleration: with
    // drag, the speed it can reach.
    const double f = loads.f_W.norm() + loads.f_P.norm();
    const double inv_m = lin.inv_m.maxCoeff();
    const double a = lin.g.norm() + inv_m * f;
    const double v = start.v.norm() + a * len;
    a_max = a + lin.gamma * v;
    if constexpr (Traits::kTurns) {
      // The torque's largest size at any orientation (loads.hpp: the lever term is fr's
      // antisymmetric part turned, at most its Frobenius norm).
      const double tau = loads.tau_P.norm() + loads.tau_W.norm() + loads.fr.norm();
      const Vec3 w0 = rot.omega(start.spin);
      double inv_I_max, inv_I_min;
      if constexpr (K == BodyMotion::kSteadySpin) {
        inv_I_max = inv_I_min = rot.inv_I;
      } else {
        inv_I_max = rot.inv_I.maxCoeff();
        inv_I_min = rot.inv_I.minCoeff();
      }
      // |w| grows at most by |I^-1 tau| over the sub-step; the gyroscopic term turns w but, for
      // the momentum's size, does not grow it: |w| <= |h| / I_min with |h| <= |h0| + tau t.
      double h0;
      if constexpr (K == BodyMotion::kSteadySpin) {
        h0 = rot.inv_I > 0.0 ? start.spin.norm() / rot.inv_I : 0.0;
      } else {
        h0 = start.spin.norm();
      }
      w_max = std::max(w0.norm() + inv_I_max * tau * len, inv_I_max * (h0 + tau * len));
      alpha_max = inv_I_max * (tau + rot.k * w_max) + inv_I_max * w_max * (h0 + tau * len);
      (void)inv_I_min;
    } else {
      w_max = alpha_max = 0.0;
    }
  }

  Motion motion_at(double s) const {
    Motion b = start_;
    if (s == 0.0) return b;
    if constexpr (!Traits::kTurns) {
      detail::translate(detail::trans_coef(lin_.gamma, s), lin_.accel(loads_.force_W(b.q)), b.x,
                        b.v);
      return b;
    } else {
      if (quiet_) {
        detail::translate(detail::trans_coef(lin_.gamma, s), lin_.accel(loads_.f_W), b.x, b.v);
        drift(b, s);
        return b;
      }
      using J = detail::TripleJump;
      const Vec3 rates = rot_.drag_rates();
      Vec3 a0 = lin_.accel(loads_.force_W(b.q));
      detail::kick_angular(rot_.spin_rate(loads_.torque_P(b.q)), rates, 0.5 * J::kStage[0] * s,
                           b.spin);
      for (int k = 0; k < J::kStages; ++k) {
        const double sk = J::kStage[k] * s;
        drift(b, sk);
        const Vec3 a1 = lin_.accel(loads_.force_W(b.q));
        detail::translate(detail::trans_coef(lin_.gamma, sk), a0, a1, b.x, b.v);
        const double next = k + 1 < J::kStages ? J::kStage[k + 1] * s : 0.0;
        detail::kick_angular(rot_.spin_rate(loads_.torque_P(b.q)), rates, 0.5 * (sk + next),
                             b.spin);
        a0 = a1;
      }
      return b;
    }
  }

  contact::MotionSample at(double s) const override { return sample(motion_at(s)); }

  contact::MotionSample sample(const Motion& b) const {
    contact::MotionSample m;
    m.pose.p_WBo = b.x;
    m.v_W = b.v;
    if constexpr (Traits::kTurns) {
      m.pose.q_WB = b.q * q_BP_.conjugate();
      m.w_W = rotate(b.q, rot_.omega(b.spin));
    } else {
      m.pose.q_WB = b.q;
    }
    return m;
  }

 private:
  // The exact torque-free rotation over s.
  void drift(Motion& b, double s) const {
    if constexpr (K == BodyMotion::kSteadySpin) {
      b.q = b.q * quat_exp(s * b.spin);
    } else if constexpr (K == BodyMotion::kPrecession) {
      AxisymPlan p;
      make_axisym_plan(rot_.I.x(), rot_.I.z(), b.spin, s, p);
      Quat dq;
      advance_axisym(p, b.spin, dq);
      b.q = b.q * dq;
    } else if constexpr (K == BodyMotion::kTumbling) {
      Quat dq;
      free_rotor_step(*rotor_, b.spin, s, dq);
      b.q = b.q * dq;
    }
    renormalize(b.q);
  }

  Motion start_;
  Linear lin_;
  Rot rot_{};
  const RotorInertia* rotor_ = nullptr;
  Quat q_BP_ = Quat::Identity();
  Loads loads_;
  bool quiet_ = true;
};

// --- one World body as the contact stage sees it ---

template <BodyMotion K>
class WorldBody final : public contact::MovingBody {
 public:
  using Traits = GroupTraits<K>;

  WorldBody(detail::Group<K> g, int i) : g_(g), i_(i) {}

  contact::MotionSample state() const override { return path_.sample(g_.motion(i_)); }

  const contact::Trajectory& plan(double length, const contact::SupportLoad& support) override {
    Loads loads = g_.entries.load_value(i_);
    if (!support.f_W.isZero(0)) loads.add_force(support.f_W, Vec3::Zero(), false);
    if (!support.tau_W.isZero(0)) loads.add_torque(support.tau_W, false);
    path_.plan(g_.motion(i_), g_.linear(i_), rot(), rotor(), q_BP(), loads, length);
    return path_;
  }

  void advance(double s) override {
    g_.motion(i_) = path_.motion_at(s);
    stale();
  }

  void set_velocity(const Vec3& v_W, const Vec3& w_W) override {
    Motion& b = g_.motion(i_);
    const Linear& lin = g_.linear(i_);
    for (int a = 0; a < 3; ++a)
      b.v[a] = lin.inv_m[a] > 0.0 ? v_W[a] : 0.0;
    if constexpr (Traits::kTurns) {
      const Vec3 w_P = b.q.conjugate() * w_W;
      if constexpr (K == BodyMotion::kSteadySpin) {
        const detail::SpinRot& r = rot();
        b.spin = r.hinge != 0.0 ? Vec3(r.axis * r.axis.dot(w_P)) : w_P;
      } else {
        b.spin = rot().spin_of(w_P);
      }
    } else {
      (void)w_W;
    }
    stale();
  }

  void shift(const Vec3& d_W) override {
    Motion& b = g_.motion(i_);
    const Linear& lin = g_.linear(i_);
    for (int a = 0; a < 3; ++a)
      if (lin.inv_m[a] > 0.0) b.x[a] += d_W[a];
  }

  contact::Response response() const override {
    contact::Response r;
    r.inv_m = g_.linear(i_).inv_m;
    if constexpr (Traits::kTurns) {
      const Mat3 R = g_.motion(i_).q.toRotationMatrix();
      Mat3 inv_I_P;
      if constexpr (K == BodyMotion::kSteadySpin) {
        const detail::SpinRot& s = rot();
        inv_I_P = s.hinge != 0.0 ? Mat3(s.inv_I * s.axis * s.axis.transpose())
                                 : Mat3(s.inv_I * Mat3::Identity());
      } else {
        inv_I_P = rot().inv_I.asDiagonal();
      }
      r.inv_I_W = R * inv_I_P * R.transpose();
    }
    return r;
  }

  void free_accelerations(Vec3& a_W, Vec3& alpha_W) const override {
    const Motion& b = g_.motion(i_);
    const Linear& lin = g_.linear(i_);
    const Loads L = g_.entries.load_value(i_);
    a_W = lin.accel(L.force_W(b.q)) - lin.gamma * b.v;
    alpha_W.setZero();
    if constexpr (Traits::kTurns) {
      const auto& r = rot();
      const Vec3 w_P = r.omega(b.spin);
      Vec3 alpha_P;
      if constexpr (K == BodyMotion::kSteadySpin) {
        alpha_P = r.alpha(L.torque_P(b.q) - r.k * w_P);
      } else {
        alpha_P = r.inv_I.cwiseProduct(L.torque_P(b.q) - w_P.cross(b.spin) - r.k * w_P);
      }
      alpha_W = rotate(b.q, alpha_P);
    }
  }

  double kinetic_energy() const override {
    const Motion& b = g_.motion(i_);
    const Linear& lin = g_.linear(i_);
    double e = 0.0;
    for (int a = 0; a < 3; ++a)
      if (lin.inv_m[a] > 0.0) e += 0.5 * b.v[a] * b.v[a] / lin.inv_m[a];
    if constexpr (K == BodyMotion::kSteadySpin) {
      if (rot().inv_I > 0.0) e += 0.5 * b.spin.squaredNorm() / rot().inv_I;
    } else if constexpr (Traits::kTurns) {
      e += 0.5 * rot().omega(b.spin).dot(b.spin);
    }
    return e;
  }

  double energy() const override {
    const Motion& b = g_.motion(i_);
    const Linear& lin = g_.linear(i_);
    double e = kinetic_energy();
    for (int a = 0; a < 3; ++a)
      if (lin.inv_m[a] > 0.0) e -= lin.g[a] * b.x[a] / lin.inv_m[a];
    return e;
  }

  bool conservative() const override {
    const auto& h = g_.entries.loads[i_];
    return h.flags == 0 && h.f_W.isZero(0);
  }

 private:
  const typename Traits::Rot& rot() const {
    if constexpr (Traits::kTurns) {
      return g_.rot(i_);
    } else {
      static constexpr detail::None kNone{};
      return kNone;
    }
  }
  const RotorInertia* rotor() const {
    if constexpr (K == BodyMotion::kTumbling) {
      return &g_.rotor(i_);
    } else {
      return nullptr;
    }
  }
  Quat q_BP() const {
    if constexpr (Traits::kPrincipalFrame) {
      return g_.q_BP(i_);
    } else {
      return Quat::Identity();
    }
  }
  void stale() {
    if constexpr (Traits::kTurns) g_.entries.plan_ok[i_] = 0;
  }

  detail::Group<K> g_;
  int i_;
  BodyPath<K> path_;
};

std::string fmt(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

void check_surface(const Surface& s, int body, const std::string& who) {
  if (!(s.restitution >= 0.0 && s.restitution <= 1.0)) {
    throw SpecError(body, "material.restitution",
                    who + ": material.restitution must be in [0, 1], got " + fmt(s.restitution));
  }
  if (!(std::isfinite(s.friction) && s.friction >= 0.0)) {
    throw SpecError(body, "material.friction",
                    who + ": material.friction must be finite and >= 0, got " + fmt(s.friction));
  }
}

void check_shape(const Shape& s, int body, const std::string& who) {
  const bool sized = s.size.allFinite() && s.size.x() > 0.0 &&
                     (s.kind == ShapeKind::kSphere ||
                      ((s.kind == ShapeKind::kBox || s.kind == ShapeKind::kEllipsoid)
                           ? (s.size.y() > 0.0 && s.size.z() > 0.0)
                           : s.size.z() > 0.0));
  if (!sized) throw SpecError(body, "shape", who + ": shape sizes must be finite and > 0");
}

}  // namespace

// --- building ---

void World::Impl::build_contacts(const WorldSpec& spec, detail::Model& model) {
  detail::ContactModel& c = model.contact;
  c = detail::ContactModel{};
  if (spec.planes.empty() && spec.statics.empty()) return;
  std::vector<std::string> names;
  for (const PlaneSpec& p : spec.planes) {
    const std::string who = "plane '" + p.name + "'";
    if (!p.n_W.allFinite() || !(p.n_W.norm() > 0.0) || !std::isfinite(p.offset)) {
      throw SpecError(-1, "plane",
                      who + ": the normal must be finite and non-zero, the offset finite");
    }
    check_surface(p.surface, -1, who);
    contact::StaticPart part;
    part.kind = contact::StaticPart::Kind::kPlane;
    part.n_W = p.n_W.normalized();
    part.offset = p.offset;
    part.surface = p.surface;
    c.parts.push_back(part);
    names.push_back(p.name);
  }
  for (const StaticSpec& s : spec.statics) {
    const std::string who = "static '" + s.name + "'";
    check_shape(s.shape, -1, who);
    if (s.shape.kind == ShapeKind::kEllipsoid) {
      throw SpecError(-1, "static", who + ": a static shape is a box, sphere, capsule or cylinder");
    }
    if (!s.p_WS.allFinite() || !s.q_WS.coeffs().allFinite() || !(s.q_WS.norm() > 1e-6)) {
      throw SpecError(-1, "static", who + ": position and orientation must be finite");
    }
    check_surface(s.surface, -1, who);
    contact::StaticPart part;
    part.kind = contact::StaticPart::Kind::kShape;
    part.convex = contact::Convex::of(s.shape);
    part.p_WS = s.p_WS;
    part.q_WS = s.q_WS.normalized();
    part.surface = s.surface;
    c.parts.push_back(part);
    names.push_back(s.name);
  }
  {
    std::vector<std::string> sorted = names;
    std::sort(sorted.begin(), sorted.end());
    for (std::size_t k = 0; k < sorted.size(); ++k) {
      if (sorted[k].empty()) throw SpecError(-1, "static", "a static part has an empty name");
      if (k > 0 && sorted[k] == sorted[k - 1]) {
        throw SpecError(-1, "static", "duplicate static part name '" + sorted[k] + "'");
      }
    }
  }
  c.part_names = std::move(names);
  // Per body its shape and surface, interned by value.
  const int n = static_cast<int>(spec.bodies.size());
  c.shape_of.resize(n);
  c.surface_of.resize(n);
  c.collides.resize(n);
  for (int i = 0; i < n; ++i) {
    const BodySpec& b = spec.bodies[i];
    const std::string who = "body '" + b.name + "'";
    if (b.shape) check_shape(*b.shape, i, who);
    check_surface(b.surface, i, who);
    const contact::Convex cv = contact::Convex::of(b.shape);
    const auto same_shape = [&](const contact::Convex& o) {
      return o.kind == cv.kind && o.half == cv.half && o.radius == cv.radius;
    };
    auto it = std::find_if(c.shapes.begin(), c.shapes.end(), same_shape);
    if (it == c.shapes.end()) it = c.shapes.insert(c.shapes.end(), cv);
    c.shape_of[i] = static_cast<std::int32_t>(it - c.shapes.begin());
    const auto same_surface = [&](const Surface& o) {
      return o.restitution == b.surface.restitution && o.friction == b.surface.friction;
    };
    auto jt = std::find_if(c.surfaces.begin(), c.surfaces.end(), same_surface);
    if (jt == c.surfaces.end()) jt = c.surfaces.insert(c.surfaces.end(), b.surface);
    c.surface_of[i] = static_cast<std::int32_t>(jt - c.surfaces.begin());
    c.collides[i] = b.kinematic ? 0 : 1;
  }
}

void World::Impl::reset_contacts() {
  const detail::ContactModel& cm = model().contact;
  detail::ContactData& c = data.contact;
  if (!cm.enabled()) {
    c = detail::ContactData{};
    return;
  }
  const int n = body_count();
  // Bodies held at rest go back to their own translation rows.
  if (c.held_linear.size() == static_cast<std::size_t>(n)) {
    for (int id = 0; id < n; ++id) {
      if (c.held_linear[id] >= 0) {
        with_body(id, [&](auto g, int i) { g.entries.linear[i] = c.held_linear[id]; });
      }
    }
  }
  c.support.assign(n, contact::SupportState{});
  c.held_linear.assign(n, -1);
  c.schedule.reset(n);
  c.watched.clear();
  c.watched.reserve(n);
  c.next_watched.clear();
  c.next_watched.reserve(n);
  c.active.clear();
  c.active.reserve(n);
  c.start.clear();
  c.start.reserve(n);
  c.events.clear();
  c.events.reserve(detail::kMaxContactEvents);
  c.dropped = 0;
  c.capped = 0;
  // Every body that takes part is looked at in the first step (the reach of each is worked out
  // from its state there).
  for (int id = 0; id < n; ++id) {
    if (cm.collides[id]) c.schedule.at(id, 0);
  }
}

void World::Impl::reserve_contacts() {
  detail::ContactData& c = data.contact;
  const std::size_t n = static_cast<std::size_t>(body_count());
  if (!model().contact.enabled()) return;
  c.schedule.reserve();
  c.watched.reserve(n);
  c.next_watched.reserve(n);
  c.active.reserve(n);
  c.start.reserve(n);
  c.events.reserve(detail::kMaxContactEvents);
}

// --- waking ---

void World::Impl::contact_wake(int id) {
  const detail::ContactModel& cm = model().contact;
  detail::ContactData& c = data.contact;
  if (!cm.enabled() || c.support.empty() || !cm.collides[id]) return;
  contact::SupportState& st = c.support[id];
  if (c.held_linear[id] >= 0) {
    with_body(id, [&](auto g, int i) { g.entries.linear[i] = c.held_linear[id]; });
    c.held_linear[id] = -1;
  }
  st.settled = false;
  // Looked at in the next step whatever it does (a supported body is watched already).
  c.schedule.at(id, data.steps);
}

void World::Impl::contact_state_set(int id) {
  const detail::ContactModel& cm = model().contact;
  if (!cm.enabled() || data.contact.support.empty() || !cm.collides[id]) return;
  contact_wake(id);
  // Placed anew: free until the stage finds what it touches.
  data.contact.support[id] = contact::SupportState{};
}

// --- the stage ---

namespace {

// The reach bound of a body's state (contact/reach.hpp): when it could first touch a part.
template <class G>
double reach_time(const detail::ContactModel& cm, G g, int i, double rho) {
  const Motion& b = g.motion(i);
  const Linear& lin = g.linear(i);
  const detail::LoadsRef L = g.load(i);
  const double f = L.f_W.norm() + L.f_P.norm();
  const double a = lin.g.norm() + lin.inv_m.maxCoeff() * f;
  return contact::time_to_reach(contact::clearance(cm.parts, b.x, rho), b.v.norm(), a);
}

}  // namespace

void World::Impl::contact_prepare() {
  const detail::ContactModel& cm = model().contact;
  detail::ContactData& c = data.contact;
  const double dt = model().dt;
  // The bodies due this step, those whose reach falls within it watched from now on.
  c.next_watched.clear();
  c.schedule.take_due(data.steps, [&](int id) {
    if (data.frozen[id]) return;
    const double rho = cm.shapes[cm.shape_of[id]].bounding_radius();
    const double t = with_body(id, [&](auto g, int i) { return reach_time(cm, g, i, rho); });
    if (t <= dt || c.support[id].phase != contact::SupportState::Phase::kFree) {
      c.next_watched.push_back(id);
    } else {
      c.schedule.at(id, data.steps + static_cast<std::int64_t>(std::floor(t / dt)));
    }
  });
  // active = watched + due, ascending and without repeats.
  std::sort(c.next_watched.begin(), c.next_watched.end());
  c.active.clear();
  std::set_union(c.watched.begin(), c.watched.end(), c.next_watched.begin(), c.next_watched.end(),
                 std::back_inserter(c.active));  // within the capacity
  c.start.clear();
  for (const int id : c.active)
    c.start.push_back(motion(id));
}

void World::Impl::contact_stage() {
  const detail::ContactModel& cm = model().contact;
  detail::ContactData& c = data.contact;
  const double dt = model().dt;
  const double t0 = static_cast<double>(data.steps) * dt;
  c.next_watched.clear();
  for (std::size_t k = 0; k < c.active.size(); ++k) {
    const int id = c.active[k];
    if (data.frozen[id]) continue;
    contact::SupportState& st = c.support[id];
    if (st.phase == contact::SupportState::Phase::kResting && st.settled &&
        c.held_linear[id] >= 0) {
      continue;  // held: the kernels left it where it was
    }
    const contact::Convex& shape = cm.shapes[cm.shape_of[id]];
    const Surface& surface = cm.surfaces[cm.surface_of[id]];
    const Motion start = c.start[k];
    const bool was_free = st.phase == contact::SupportState::Phase::kFree;
    // The parts within the body's reach over the step (all, for a handful of parts).
    std::int32_t candidates[contact::kMaxPoints];
    int n_candidates = 0;
    {
      const double rho = shape.bounding_radius();
      const double reach = with_body(id, [&](auto g, int i) {
        const Linear& lin = g.linear(i);
        const detail::LoadsRef L = g.load(i);
        const double a = lin.g.norm() + lin.inv_m.maxCoeff() * (L.f_W.norm() + L.f_P.norm());
        return (start.v.norm() + 0.5 * a * dt) * dt;
      });
      for (int p = 0; p < static_cast<int>(cm.parts.size()); ++p) {
        const std::span<const contact::StaticPart> one(&cm.parts[p], 1);
        if (contact::clearance(one, start.x, rho) > reach + 1e-9 * (1.0 + start.x.norm())) continue;
        if (n_candidates < contact::kMaxPoints) candidates[n_candidates++] = p;
      }
    }
    if (was_free && n_candidates == 0) {
      // Nothing within reach: the kernel's state stands.
      after_free(id);
      continue;
    }
    with_body(id, [&](auto g, int i) {
      using G = decltype(g);
      WorldBody<G::kKind> body(g, i);
      const Motion end = g.motion(i);
      g.motion(i) = start;
      const contact::ContactBody cb{id, &shape, surface,
                                    std::span<const std::int32_t>(candidates, n_candidates)};
      if (was_free) {
        // Does its step touch anything? If not, the kernel's state stands.
        const contact::Trajectory& tr = body.plan(dt, contact::SupportLoad{});
        bool touches = false;
        for (int p = 0; p < n_candidates && !touches; ++p)
          touches = contact::first_touch(shape, cm.parts[candidates[p]], tr, 0.0).found;
        if (!touches) {
          g.motion(i) = end;
          return;
        }
      }
      if constexpr (GroupTraits<G::kKind>::kTurns) g.entries.plan_ok[i] = 0;
      const std::size_t used = c.events.size();
      c.events.resize(detail::kMaxContactEvents);  // within the reserved capacity
      contact::EventSink sink(c.events.data() + used,
                              detail::kMaxContactEvents - static_cast<int>(used));
      const contact::ContactStepResult r = contact::contact_step(body, cb, cm.parts, dt, st, sink);
      c.events.resize(used + static_cast<std::size_t>(sink.size()));
      for (std::size_t e = used; e < c.events.size(); ++e)
        c.events[e].time += t0;
      c.dropped += sink.dropped();
      c.capped += r.capped ? 1 : 0;
    });
    if (st.phase == contact::SupportState::Phase::kFree) {
      after_free(id);
    } else if (st.phase == contact::SupportState::Phase::kResting && st.settled) {
      hold(id);
    } else {
      c.next_watched.push_back(id);
    }
  }
  c.watched.swap(c.next_watched);
}

// A free body after its step: watched if it could touch a part within the next step, else due
// when its reach says.
void World::Impl::after_free(int id) {
  const detail::ContactModel& cm = model().contact;
  detail::ContactData& c = data.contact;
  const double dt = model().dt;
  const double rho = cm.shapes[cm.shape_of[id]].bounding_radius();
  const double t = with_body(id, [&](auto g, int i) { return reach_time(cm, g, i, rho); });
  if (t <= dt) {
    c.next_watched.push_back(id);
  } else {
    c.schedule.at(id, data.steps + 1 + static_cast<std::int64_t>(std::floor(t / dt)));
  }
}

// A body come to rest with nothing turning it: held by the still translation row (the kernels then
// leave it exactly in place); a loaded one stays watched, its rest made again each step.
void World::Impl::hold(int id) {
  detail::ContactData& c = data.contact;
  const bool quiet = load(id).quiet() && load(id).f_W.isZero(0);
  if (!quiet) {
    c.support[id].settled = false;
    c.next_watched.push_back(id);
    return;
  }
  with_body(id, [&](auto g, int i) {
    c.held_linear[id] = g.entries.linear[i];
    g.entries.linear[i] = 0;
    Motion& m = g.motion(i);
    m.v.setZero();
    m.spin.setZero();
    if constexpr (decltype(g)::Traits::kTurns) g.entries.plan_ok[i] = 0;
  });
}

// --- the API ---

int World::static_part_count() const {
  return static_cast<int>(impl_->model().contact.parts.size());
}
std::string_view World::static_part_name(int part) const {
  const detail::ContactModel& cm = impl_->model().contact;
  if (part < 0 || part >= static_cast<int>(cm.parts.size())) {
    throw std::out_of_range("no static part " + std::to_string(part));
  }
  return cm.part_names[part];
}
std::span<const ContactEvent> World::contact_events() const {
  return impl_->data.contact.events;
}
std::int64_t World::contact_events_dropped() const {
  return impl_->data.contact.dropped;
}
std::int64_t World::contact_capped_steps() const {
  return impl_->data.contact.capped;
}
World::Support World::support(int id) const {
  impl_->check_id(id);
  const detail::ContactData& c = impl_->data.contact;
  if (c.support.empty()) return Support::kFree;
  switch (c.support[id].phase) {
    case contact::SupportState::Phase::kFree:
      return Support::kFree;
    case contact::SupportState::Phase::kResting:
      return Support::kResting;
    case contact::SupportState::Phase::kSliding:
      return Support::kSliding;
    case contact::SupportState::Phase::kRolling:
      return Support::kRolling;
  }
  return Support::kFree;
}

}  // namespace rigid::physics
