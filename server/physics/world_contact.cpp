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
#include <numeric>

#include "physics/contact/contact_step.hpp"
#include "physics/contact/reach.hpp"
#include "physics/contact/time_of_impact.hpp"
#include "physics/free_rotor.hpp"
#include "physics/kernels.hpp"
#include "physics/translation.hpp"
#include "physics/world_body.hpp"
#include "physics/world_impl.hpp"

namespace rigid::physics {

using detail::ConstGroup;
using detail::GroupTraits;
using detail::Linear;
using detail::Loads;
using detail::Motion;

namespace {

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

// Whether the bodies' collision filters let any two of them meet (a scene whose filters keep
// every body apart, such as copies that each meet only the parts, has no pair stage). Checked over
// the distinct (group, mask) filters, which are few; beyond 64 of them, assumed so.
bool filters_admit_a_pair(const std::vector<BodySpec>& bodies) {
  struct Filter {
    std::uint32_t group, mask;
    int count;
  };
  std::vector<Filter> filters;
  for (const BodySpec& b : bodies) {
    auto it = std::find_if(filters.begin(), filters.end(), [&](const Filter& f) {
      return f.group == b.collision_group && f.mask == b.collision_mask;
    });
    if (it != filters.end()) {
      ++it->count;
    } else if (filters.size() == 64) {
      return true;
    } else {
      filters.push_back({b.collision_group, b.collision_mask, 1});
    }
  }
  for (std::size_t i = 0; i < filters.size(); ++i) {
    for (std::size_t j = i; j < filters.size(); ++j) {
      const Filter& a = filters[i];
      const Filter& b = filters[j];
      if ((a.group & b.mask) != 0 && (b.group & a.mask) != 0 && (i != j || a.count >= 2))
        return true;
    }
  }
  return false;
}

}  // namespace

// --- building ---

void World::Impl::build_contacts(const WorldSpec& spec, detail::Model& model) {
  detail::ContactModel& c = model.contact;
  c = detail::ContactModel{};
  // Bodies can meet each other when two of them could: at least two that collide, not all points
  // (a scene of point masses, or of one body, has no contacts between bodies).
  int collidable = 0, shaped = 0;
  for (const BodySpec& b : spec.bodies) {
    collidable += b.kinematic ? 0 : 1;
    shaped += b.shape ? 1 : 0;
  }
  const bool pairs = collidable >= 1 && spec.bodies.size() >= 2 && shaped >= 1 &&
                     filters_admit_a_pair(spec.bodies);
  if (spec.planes.empty() && spec.statics.empty() && !pairs) return;
  c.pairs = pairs;
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
  c.group.resize(n);
  c.mask.resize(n);
  for (int i = 0; i < n; ++i) {
    c.group[i] = spec.bodies[i].collision_group;
    c.mask[i] = spec.bodies[i].collision_mask;
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
  c.watched.reserve(2 * n);  // swapped with next_watched each step
  c.next_watched.clear();
  c.next_watched.reserve(2 * n);  // the due bodies, then the islands' (each at most n)
  c.active.clear();
  c.active.reserve(n);
  c.start.clear();
  c.start.reserve(n);
  c.events.clear();
  c.events.reserve(detail::kMaxContactEvents);
  c.scratch.resize(detail::kMaxContactEvents);
  c.dropped = 0;
  c.capped = 0;
  c.boxes.assign(n, detail::SweptBox{});
  c.order.resize(n);
  std::iota(c.order.begin(), c.order.end(), 0);
  c.candidates.clear();
  c.candidates.reserve(cm.pairs ? 16 * static_cast<std::size_t>(n) : 0);
  c.next_broad = 0;
  c.look_ahead = detail::kMinLookAhead;
  c.close.clear();
  c.close.reserve(cm.pairs ? 16 * static_cast<std::size_t>(n) : 0);
  c.root.assign(n, -1);
  c.island_ids.clear();
  c.island_ids.reserve(cm.pairs ? 2 * static_cast<std::size_t>(n) : 0);
  c.ibodies.clear();
  c.ibodies.reserve(cm.pairs ? static_cast<std::size_t>(n) : 0);
  c.irows.clear();
  c.irows.reserve(cm.pairs ? 16 * static_cast<std::size_t>(n) : 0);
  c.ilocal.assign(n, -1);
  c.calm.assign(n, 0);
  c.sleep_group.assign(n, -1);
  c.warm.clear();
  c.next_warm.clear();
  c.warm.reserve(cm.pairs ? 2 * static_cast<std::size_t>(n) : 0);
  c.next_warm.reserve(cm.pairs ? 2 * static_cast<std::size_t>(n) : 0);
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
  c.watched.reserve(2 * n);       // swapped with next_watched each step
  c.next_watched.reserve(2 * n);  // the due bodies, then the islands' (each at most n)
  c.active.reserve(n);
  c.start.reserve(n);
  c.events.reserve(detail::kMaxContactEvents);
  c.scratch.resize(detail::kMaxContactEvents);
  if (model().contact.pairs) {
    c.candidates.reserve(16 * n);
    c.close.reserve(16 * n);
    c.island_ids.reserve(2 * n);
    c.ibodies.reserve(n);
    c.irows.reserve(16 * n);
    c.warm.reserve(2 * n);
    c.next_warm.reserve(2 * n);
  }
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
  // Looked at in the next step whatever it does (a supported body is watched already), and the
  // broad phase's bounds, which its loads or state gave, made again.
  c.schedule.at(id, data.steps);
  if (cm.pairs) {
    c.next_broad = data.steps;
    c.look_ahead = detail::kMinLookAhead;
  }
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
    } else if (std::isfinite(t) && t / dt < 1e15) {
      c.schedule.at(id, data.steps + static_cast<std::int64_t>(std::floor(t / dt)));
    }
  });
  // Ascending and without repeats (a body can be due twice); then the islands' bodies, each once,
  // join them: at most 2 n, within the reserve.
  std::sort(c.next_watched.begin(), c.next_watched.end());
  c.next_watched.erase(std::unique(c.next_watched.begin(), c.next_watched.end()),
                       c.next_watched.end());
  if (cm.pairs) {
    pairs_prepare();
    std::sort(c.next_watched.begin(), c.next_watched.end());
    c.next_watched.erase(std::unique(c.next_watched.begin(), c.next_watched.end()),
                         c.next_watched.end());
  }
  // active = watched + due (+ the islands' bodies), ascending and without repeats.
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
    if (c.root[id] >= 0) continue;  // in an island: world_pairs.cpp steps it
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
      detail::WorldBody<G::kKind> body(g, i);
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
      contact::EventSink sink(c.scratch.data(), detail::kMaxContactEvents - static_cast<int>(used));
      const contact::ContactStepResult r = contact::contact_step(body, cb, cm.parts, dt, st, sink);
      // Within the reserved capacity.
      c.events.insert(c.events.end(), c.scratch.begin(), c.scratch.begin() + sink.size());
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
  if (cm.pairs) pairs_stage();
  std::sort(c.next_watched.begin(), c.next_watched.end());
  c.next_watched.erase(std::unique(c.next_watched.begin(), c.next_watched.end()),
                       c.next_watched.end());
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
  } else if (std::isfinite(t) && t / dt < 1e15) {
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
