// Bodies against bodies in the World's contact stage: the broad phase, the islands of bodies that
// may touch within a step, and each island's step.
//
// Broad phase: sweep and prune over swept boxes (each body's bounding sphere grown by how far it
// can move over a look-ahead of some steps, in the frame that falls with gravity, so that bodies
// falling together do not look as if they closed in), its order kept from one run to the next
// (insertion sort: O(n) while bodies keep their order). It runs again when its look-ahead is over,
// or at the next step after a body's loads or state change. The look-ahead is kMinLookAhead steps,
// doubled after each run that finds no pair up to kMaxLookAhead: a world whose bodies stay apart
// pays one run per kMaxLookAhead steps.
//
// Each step, the broad phase's pairs that may touch within the step (their bounding spheres' gap
// within the relative motion's reach) join their bodies into islands. An island is stepped as one:
//   - while all its bodies fly free, by events, as a single body is (contact_step.hpp): advanced
//     together to the first touch of any two of them or of one with a part, found on their own
//     trajectories; the impacts there resolved one contact at a time, the fastest-closing first,
//     until none closes in (so that a row of touching balls passes a blow along: Newton's cradle
//     sends one ball out), each contact's points together (a face lands flat without spin);
//   - once bodies rest on each other, by time stepping: the contact impulses over the rest of the
//     step solved together for every point of the island (island_solver.hpp), from the velocities
//     the bodies would reach without them, with each contact allowed to close at most its gap;
//     the bodies then move under those impulses as constant forces, any overlap left is taken back
//     along the normals, and the island's energy under gravity alone may not rise.
// A stepped island whose bodies all stay slower than kSleepSpeed for kSleepSteps steps sleeps: its
// bodies are held at rest (world_contact.cpp: hold) until something touches or loads one of them.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <tuple>

#include "physics/contact/pair_gap.hpp"
#include "physics/contact/reach.hpp"
#include "physics/contact/time_of_impact.hpp"
#include "physics/world_body.hpp"
#include "physics/world_impl.hpp"

namespace rigid::physics {

using detail::Linear;
using detail::Motion;
using Phase = contact::SupportState::Phase;

namespace {

// The features of a resting contact: the points of each body within this of its support plane
// (a fiftieth of the smaller body's size). A face tilted a little on another keeps its four
// corners in the contact, the lifted ones free to close their gap: what keeps a stack square.
double feature_tol(const contact::Convex& a, const contact::Convex& b) {
  return 0.02 * std::min(a.bounding_radius(), b.bounding_radius()) + 1e-9;
}

// An island's bodies slower than this (m/s, and rad/s times their size) for kSleepSteps steps in a
// row sleep.
constexpr double kSleepSpeed = 1e-3;
constexpr int kSleepSteps = 200;
// Bodies of an island closer than this are in contact (a resting stack's faces).
constexpr double kSlop = 1e-6;
// The most events an island's step is split at before it is taken by time stepping.
constexpr int kMaxIslandEvents = 64;

int find(std::vector<int>& root, int i) {
  while (root[i] != i) {
    root[i] = root[root[i]];
    i = root[i];
  }
  return i;
}

}  // namespace

// The broad phase's bound on body id's motion: its speed and, in the frame falling with the
// world's gravity, its acceleration.
void World::Impl::motion_bounds(int id, double& speed, double& accel) const {
  const Vec3 g = model().g_W;
  with_body(id, [&](auto gr, int i) {
    const Motion& b = gr.motion(i);
    const Linear& lin = gr.linear(i);
    const detail::LoadsRef L = gr.load(i);
    speed = b.v.norm();
    accel = (lin.g - g).norm() + lin.inv_m.maxCoeff() * (L.f_W.norm() + L.f_P.norm()) +
            lin.gamma * speed;
  });
}

void World::Impl::broad_phase() {
  const detail::ContactModel& cm = model().contact;
  detail::ContactData& c = data.contact;
  const double T = c.look_ahead * model().dt;
  const int n = body_count();
  for (int id = 0; id < n; ++id) {
    double v, a;
    motion_bounds(id, v, a);
    const Vec3& x = motion(id).x;
    // Grown by the contact slop too: bodies touching at round-off keep their boxes overlapping.
    const double r = cm.shapes[cm.shape_of[id]].bounding_radius() + v * T + 0.5 * a * T * T +
                     kSlop + 1e-12 * x.norm();
    c.boxes[id] = detail::SweptBox{x - Vec3::Constant(r), x + Vec3::Constant(r)};
  }
  // Insertion sort by lo.x from the last order: linear while the order barely changes.
  std::vector<int>& o = c.order;
  for (std::size_t k = 1; k < o.size(); ++k) {
    const int id = o[k];
    const double key = c.boxes[id].lo.x();
    std::size_t j = k;
    while (j > 0 && c.boxes[o[j - 1]].lo.x() > key) {
      o[j] = o[j - 1];
      --j;
    }
    o[j] = id;
  }
  c.candidates.clear();
  for (std::size_t k = 0; k < o.size(); ++k) {
    const int a = o[k];
    if (!cm.collides[a] && cm.shapes[cm.shape_of[a]].kind == contact::Convex::Kind::kPoint)
      continue;
    const detail::SweptBox& A = c.boxes[a];
    for (std::size_t j = k + 1; j < o.size(); ++j) {
      const int b = o[j];
      const detail::SweptBox& B = c.boxes[b];
      if (B.lo.x() > A.hi.x()) break;
      if (B.lo.y() > A.hi.y() || A.lo.y() > B.hi.y() || B.lo.z() > A.hi.z() || A.lo.z() > B.hi.z())
        continue;
      if (!cm.collides[a] && !cm.collides[b]) continue;  // two kinematic bodies
      if (!cm.may_collide(a, b)) continue;
      c.candidates.emplace_back(std::min(a, b), std::max(a, b));  // grows past its reserve only
                                                                  // in a dense pile
    }
  }
  std::sort(c.candidates.begin(), c.candidates.end());
  c.next_broad = data.steps + c.look_ahead;
  c.look_ahead = c.candidates.empty() ? std::min(2 * c.look_ahead, detail::kMaxLookAhead)
                                      : detail::kMinLookAhead;
}

void World::Impl::pairs_prepare() {
  const detail::ContactModel& cm = model().contact;
  detail::ContactData& c = data.contact;
  const double dt = model().dt;
  if (data.steps >= c.next_broad) broad_phase();
  // The pairs that may touch within this step, and their islands.
  c.close.clear();
  for (const auto& [a, b] : c.candidates) {
    if (data.frozen[a] || data.frozen[b]) continue;
    const bool held_a = c.held_linear[a] >= 0, held_b = c.held_linear[b] >= 0;
    if (held_a && held_b) continue;  // both asleep
    double va, aa, vb, ab;
    motion_bounds(a, va, aa);
    motion_bounds(b, vb, ab);
    const Vec3 dx = motion(a).x - motion(b).x;
    const double gap = dx.norm() - cm.shapes[cm.shape_of[a]].bounding_radius() -
                       cm.shapes[cm.shape_of[b]].bounding_radius();
    const double reach = (motion(a).v - motion(b).v).norm() * dt + 0.5 * (aa + ab) * dt * dt;
    if (gap > reach + kSlop) continue;
    c.close.emplace_back(a, b);
  }
  if (c.close.empty()) return;
  // Each body of a close pair once (at most every body: within island_ids' reserve).
  c.island_ids.clear();
  for (const auto& [a, b] : c.close) {
    for (const int id : {a, b}) {
      if (c.root[id] >= 0) continue;
      c.root[id] = id;
      c.island_ids.push_back(id);
    }
  }
  for (const auto& [a, b] : c.close) {
    const int ra = find(c.root, a), rb = find(c.root, b);
    if (ra != rb) c.root[std::max(ra, rb)] = std::min(ra, rb);
  }
  std::sort(c.island_ids.begin(), c.island_ids.end());
  for (const int id : c.island_ids)
    c.root[id] = find(c.root, id);
  // A sleeping body an island reaches wakes, with the group it sleeps in.
  for (std::size_t k = 0; k < c.island_ids.size(); ++k) {
    const int id = c.island_ids[k];
    if (c.sleep_group[id] >= 0) wake_group(c.sleep_group[id]);
    if (c.held_linear[id] >= 0) contact_wake(id);
  }
  // Islands' bodies join this step's active bodies (contact_prepare merges them).
  for (const int id : c.island_ids)
    c.next_watched.push_back(id);
}

void World::Impl::wake_group(int group) {
  detail::ContactData& c = data.contact;
  for (int id = 0; id < body_count(); ++id) {
    if (c.sleep_group[id] != group) continue;
    c.sleep_group[id] = -1;
    c.calm[id] = 0;
    contact_wake(id);
  }
}

// The motion of body id at the step's start (contact_prepare kept it: c.active is ascending).
const Motion& World::Impl::start_of(int id) const {
  const detail::ContactData& c = data.contact;
  const auto it = std::lower_bound(c.active.begin(), c.active.end(), id);
  return c.start[static_cast<std::size_t>(it - c.active.begin())];
}

void World::Impl::pairs_stage() {
  detail::ContactData& c = data.contact;
  if (c.island_ids.empty()) {
    c.warm.clear();
    return;
  }
  // Bodies by island (root), each island's bodies ascending; islands by their smallest body.
  // (std::sort on a total order: std::stable_sort would take a buffer from the heap.)
  std::sort(c.island_ids.begin(), c.island_ids.end(),
            [&](int x, int y) { return c.root[x] != c.root[y] ? c.root[x] < c.root[y] : x < y; });
  for (std::size_t k = 0; k < c.island_ids.size();) {
    std::size_t e = k + 1;
    while (e < c.island_ids.size() && c.root[c.island_ids[e]] == c.root[c.island_ids[k]])
      ++e;
    island_step(std::span<const int>(c.island_ids.data() + k, e - k));
    k = e;
  }
  for (const int id : c.island_ids)
    c.root[id] = -1;
  c.island_ids.clear();
  std::sort(
      c.next_warm.begin(), c.next_warm.end(),
      [](const detail::WarmContact& x, const detail::WarmContact& y) { return x.key() < y.key(); });
  c.warm.swap(c.next_warm);
  c.next_warm.clear();
}

// f(MovingBody&) for body id (world_body.hpp), made on the stack.
template <class F>
decltype(auto) World::Impl::with_moving(int id, F&& f) {
  return with_body(id, [&](auto g, int i) -> decltype(auto) {
    detail::WorldBody<decltype(g)::kKind> body(g, i);
    return f(static_cast<contact::MovingBody&>(body));
  });
}

// Every contact of the island's bodies now: pairs of them and parts, within `margin` (pairs and
// parts beyond it are left out), with their points (tolerance for a face's corners: kFeatureTol
// of contact_step, or the margin when the contact is speculative).
int World::Impl::island_contacts(std::span<const int> ids, double margin,
                                 detail::IslandContact* out, int cap) {
  const detail::ContactModel& cm = model().contact;
  detail::ContactData& c = data.contact;
  int n = 0;
  for (const auto& [a, b] : c.close) {
    if (n == cap) break;
    if (c.ilocal[a] < 0 || c.ilocal[b] < 0) continue;
    const contact::Convex& A = cm.shapes[cm.shape_of[a]];
    const contact::Convex& B = cm.shapes[cm.shape_of[b]];
    const contact::Pose pa = pose_of(a), pb = pose_of(b);
    const contact::PairGap g = contact::pair_gap(A, pa, B, pb);
    if (g.distance > margin) continue;
    detail::IslandContact& t = out[n++];
    t.a = a, t.b = b, t.part = -1;
    t.surface = contact::combine(cm.surfaces[cm.surface_of[a]], cm.surfaces[cm.surface_of[b]]);
    t.n = g.n_W;
    t.gap = g.distance;
    t.np = contact::pair_manifold(A, pa, B, pb, g, feature_tol(A, B), t.p);
  }
  for (const int id : ids) {
    const contact::Convex& A = cm.shapes[cm.shape_of[id]];
    const contact::Pose pa = pose_of(id);
    for (int k = 0; k < static_cast<int>(cm.parts.size()) && n < cap; ++k) {
      const contact::Gap g = contact::gap(A, pa, cm.parts[k]);
      if (g.distance > margin) continue;
      detail::IslandContact& t = out[n++];
      t.a = id, t.b = -1, t.part = k;
      t.surface = contact::combine(cm.surfaces[cm.surface_of[id]], cm.parts[k].surface);
      t.n = g.n_W;
      t.gap = g.distance;
      t.np = contact::touching_points(A, pa, cm.parts[k], g, feature_tol(A, A), t.p);
    }
  }
  return n;
}

contact::Pose World::Impl::pose_of(int id) const {
  return with_body(id, [&](auto g, int i) {
    const Motion& b = g.motion(i);
    contact::Pose p;
    p.p_WBo = b.x;
    if constexpr (decltype(g)::Traits::kPrincipalFrame) {
      p.q_WB = b.q * g.q_BP(i).conjugate();
    } else {
      p.q_WB = b.q;
    }
    return p;
  });
}

void World::Impl::island_step(std::span<const int> ids) {
  const detail::ContactModel& cm = model().contact;
  detail::ContactData& c = data.contact;
  const double dt = model().dt;
  const double t0 = static_cast<double>(data.steps) * dt;
  for (std::size_t k = 0; k < ids.size(); ++k) {
    const int id = ids[k];
    c.ilocal[id] = static_cast<int>(k);
    motion(id) = start_of(id);
    invalidate_cache(id);
  }
  constexpr int kCap = 256;
  detail::IslandContact touching[kCap];
  // An island that rested on itself in the last step is stepped again; otherwise its bodies go by
  // events until they come to rest on each other or on parts (bodies merely touching, with nothing
  // pressing them together, are not resting: a row of balls waits for the blow to pass on).
  bool stepped = false;
  for (const int id : ids)
    stepped = stepped || c.support[id].phase != Phase::kFree;
  double t = 0.0;
  for (int events = 0; !stepped && t < dt; ++events) {
    if (events == kMaxIslandEvents) {
      stepped = true;
      break;
    }
    const double h = dt - t;
    double first = h;
    // The first touch of two of its bodies, or of one with a part.
    for (const auto& pair : c.close) {
      // Named, not bound: clang 14 does not let a lambda capture a structured binding (P1091R3).
      const int a = pair.first, b = pair.second;
      if (c.ilocal[a] < 0 || c.ilocal[b] < 0) continue;
      with_moving(a, [&](contact::MovingBody& A) {
        with_moving(b, [&](contact::MovingBody& B) {
          const contact::Trajectory& ta = A.plan(h, contact::SupportLoad{});
          const contact::Trajectory& tb = B.plan(h, contact::SupportLoad{});
          const contact::PairTouch touch = contact::first_touch_pair(
              cm.shapes[cm.shape_of[a]], ta, cm.shapes[cm.shape_of[b]], tb, 0.0);
          if (touch.found) first = std::min(first, touch.s);
        });
      });
    }
    for (const int id : ids) {
      with_moving(id, [&](contact::MovingBody& A) {
        const contact::Trajectory& tr = A.plan(h, contact::SupportLoad{});
        for (const contact::StaticPart& part : cm.parts) {
          const contact::Touch touch =
              contact::first_touch(cm.shapes[cm.shape_of[id]], part, tr, 0.0);
          if (touch.found) first = std::min(first, touch.s);
        }
      });
    }
    for (const int id : ids) {
      with_moving(id, [&](contact::MovingBody& A) {
        A.plan(h, contact::SupportLoad{});
        A.advance(first);
      });
    }
    t += first;
    if (first == h) break;
    stepped = island_impacts(ids, t0 + t, h - first, touching, kCap);
  }
  if (stepped && t < dt) island_time_step(ids, dt - t, t0 + t, touching, kCap);
  // Afterwards: free for the single-body stage to take up, or asleep.
  bool calm = true;
  for (const int id : ids) {
    const auto [v, w] = with_body(id, [&](auto g, int i) {
      const Motion& b = g.motion(i);
      double w = 0.0;
      if constexpr (decltype(g)::Traits::kTurns) w = g.rot(i).omega(b.spin).norm();
      return std::pair<double, double>(b.v.norm(), w);
    });
    const double rho = cm.shapes[cm.shape_of[id]].bounding_radius();
    if (v > kSleepSpeed || w * rho > kSleepSpeed || !stepped) {
      c.calm[id] = 0;
      calm = false;
    } else if (c.calm[id] < kSleepSteps) {
      ++c.calm[id];
    }
  }
  for (const int id : ids)
    calm = calm && c.calm[id] >= kSleepSteps && load(id).quiet() && load(id).f_W.isZero(0);
  for (const int id : ids) {
    c.ilocal[id] = -1;
    if (calm) {
      c.support[id].phase = Phase::kResting;
      c.support[id].settled = true;
      c.sleep_group[id] = ids[0];
      hold(id);
    } else {
      // Resting on the island (stepped): looked at again next step as such; else free.
      c.support[id] = contact::SupportState{};
      if (stepped) c.support[id].phase = Phase::kRolling;
      after_free(id);
    }
  }
}

// The impacts at an instant: the contact closing in fastest resolved first, alone (its points
// together), then the next, until none closes in; a row of touching bodies so passes a blow on.
// Returns whether the island now rests on itself (a contact left touching, not parting fast
// enough for its bounces to stay apart within the step): it is then time stepped.
bool World::Impl::island_impacts(std::span<const int> ids, double time, double left,
                                 detail::IslandContact* touching, int cap) {
  detail::ContactData& c = data.contact;
  const double g = model().g_W.norm();
  // What touches now: within round-off of where the first touch left them.
  const int nt = island_contacts(ids, 1e-9, touching, cap);
  const auto body_velocity = [&](int id, const Vec3& p, Vec3& u) {
    const contact::MotionSample m =
        with_moving(id, [](contact::MovingBody& B) { return B.state(); });
    u = m.v_W + m.w_W.cross(p - m.pose.p_WBo);
    return m;
  };
  const auto closing = [&](const detail::IslandContact& t, int k) {
    Vec3 ua, ub = Vec3::Zero();
    body_velocity(t.a, t.p[k], ua);
    if (t.b >= 0) body_velocity(t.b, t.p[k], ub);
    return t.n.dot(ua - ub);
  };
  for (int round = 0; round < 16 * static_cast<int>(ids.size()) + 16; ++round) {
    int worst = -1;
    double speed = -contact::kStillSpeed;
    for (int k = 0; k < nt; ++k) {
      for (int i = 0; i < touching[k].np; ++i) {
        const double un = closing(touching[k], i);
        if (un < speed) speed = un, worst = k;
      }
    }
    if (worst < 0) break;
    const detail::IslandContact& t = touching[worst];
    // That contact alone: its one or two bodies, its points.
    c.ibodies.clear();
    c.irows.clear();
    const int bodies[2] = {t.a, t.b};
    for (int j = 0; j < (t.b >= 0 ? 2 : 1); ++j) {
      contact::IslandBody ib;
      with_moving(bodies[j], [&](contact::MovingBody& B) {
        const contact::MotionSample m = B.state();
        ib.resp = B.response();
        ib.v = m.v_W;
        ib.w = m.w_W;
      });
      c.ibodies.push_back(ib);
    }
    for (int i = 0; i < t.np; ++i) {
      contact::IslandRow r;
      r.a = 0;
      r.b = t.b >= 0 ? 1 : -1;
      r.n = t.n;
      r.r_a = t.p[i] - pose_of(t.a).p_WBo;
      if (t.b >= 0) r.r_b = t.p[i] - pose_of(t.b).p_WBo;
      r.mu = t.surface.friction;
      const double un = closing(t, i);
      r.target = un < 0.0 ? -t.surface.restitution * un : 0.0;
      c.irows.push_back(r);
    }
    contact::solve_island(c.ibodies, c.irows, 200, 1e-14);
    Vec3 J = Vec3::Zero();
    for (const contact::IslandRow& r : c.irows)
      J += r.pn * r.n + r.pt.x() * r.t1 + r.pt.y() * r.t2;
    for (int j = 0; j < static_cast<int>(c.ibodies.size()); ++j) {
      with_moving(bodies[j],
                  [&](contact::MovingBody& B) { B.set_velocity(c.ibodies[j].v, c.ibodies[j].w); });
    }
    ContactEvent e;
    e.kind = ContactEventKind::kImpact;
    e.body = t.a;
    e.part = t.part;
    e.other = t.b;
    e.time = time;
    Vec3 centre = Vec3::Zero();
    for (int i = 0; i < t.np; ++i)
      centre += t.p[i] / t.np;
    e.p_W = centre;
    e.n_W = t.n;
    e.impulse_W = J;
    push_event(e);
  }
  // Left touching and not parting fast enough to stay apart over the rest of the step.
  for (int k = 0; k < nt; ++k) {
    const double e = touching[k].surface.restitution;
    const double bounce = std::max(contact::kStillSpeed, 0.5 * g * left * (1.0 - e));
    for (int i = 0; i < touching[k].np; ++i) {
      if (closing(touching[k], i) <= bounce) return true;
    }
  }
  return false;
}

// The island's bodies resting on each other (and on parts) over h: the contact impulses over h
// solved together from the velocities the bodies would reach without them, held as constant
// forces while the bodies move, then any overlap taken back.
void World::Impl::island_time_step(std::span<const int> ids, double h, double time,
                                   detail::IslandContact* touching, int cap) {
  const detail::ContactModel& cm = model().contact;
  detail::ContactData& c = data.contact;
  // How far contacts may be and still act within h: the bodies' relative reach.
  double reach = kSlop;
  c.ibodies.clear();
  double e_start = 0.0;
  bool conservative = true;
  for (const int id : ids) {
    contact::IslandBody ib;
    with_moving(id, [&](contact::MovingBody& B) {
      const contact::MotionSample m = B.state();
      Vec3 a, alpha;
      B.free_accelerations(a, alpha);
      ib.resp = B.response();
      ib.v = m.v_W + h * a;
      ib.w = m.w_W + h * alpha;
      reach = std::max(reach, (m.v_W.norm() + a.norm() * h +
                               m.w_W.norm() * cm.shapes[cm.shape_of[id]].bounding_radius()) *
                                  h);
      e_start += B.energy();
      conservative = conservative && B.conservative();
    });
    c.ibodies.push_back(ib);
  }
  const int nt = island_contacts(ids, 2.0 * reach + kSlop, touching, cap);
  // Contacts from the ground up (parts first, then pairs by the lower body's height against
  // gravity): a Gauss-Seidel sweep then passes a stack's support up through it in one sweep.
  {
    const Vec3 up = model().g_W.norm() > 0.0 ? Vec3(-model().g_W.normalized()) : Vec3::UnitZ();
    const auto height = [&](const detail::IslandContact& t) {
      if (t.b < 0) return -std::numeric_limits<double>::infinity();
      return std::min(up.dot(pose_of(t.a).p_WBo), up.dot(pose_of(t.b).p_WBo));
    };
    // A total order (ties by the bodies and part: one contact each), for std::sort, which takes
    // no buffer from the heap as std::stable_sort would.
    std::sort(touching, touching + nt,
              [&](const detail::IslandContact& x, const detail::IslandContact& y) {
                const double hx = height(x), hy = height(y);
                if (hx != hy) return hx < hy;
                return std::tie(x.a, x.b, x.part) < std::tie(y.a, y.b, y.part);
              });
  }
  c.irows.clear();
  for (int k = 0; k < nt; ++k) {
    const detail::IslandContact& t = touching[k];
    const Vec3 xa = pose_of(t.a).p_WBo;
    const Vec3 xb = t.b >= 0 ? pose_of(t.b).p_WBo : Vec3::Zero();
    for (int i = 0; i < t.np; ++i) {
      contact::IslandRow r;
      r.a = c.ilocal[t.a];
      r.b = t.b >= 0 ? c.ilocal[t.b] : -1;
      r.n = t.n;
      r.r_a = t.p[i] - xa;
      if (t.b >= 0) r.r_b = t.p[i] - xb;
      r.mu = t.surface.friction;
      // The velocity the contact may close at: its gap over h (never more: it would overlap),
      // or, for one that closes in from apart within h, the bounce its restitution gives.
      const contact::IslandBody& A = c.ibodies[r.a];
      Vec3 u = A.v + A.w.cross(r.r_a);
      if (r.b >= 0) u -= c.ibodies[r.b].v + c.ibodies[r.b].w.cross(r.r_b);
      const double un = t.n.dot(u);
      const double gap = std::max(t.gap, 0.0);
      r.target = -gap / h;
      if (t.gap > kSlop && un * h < -gap)
        r.target = std::max(r.target, -t.surface.restitution * un);
      c.irows.push_back(r);
    }
    warm_start(t, h, c.irows.size() - static_cast<std::size_t>(t.np));
  }
  // From cold (no contact carried a force in the last step) the solve needs many sweeps to carry a
  // stack's weight down to its base; warm started, a few (a contact that joins a warm island, or
  // one that carries nothing, such as a pile's many grazing ones, starts from the others' forces).
  bool cold = true;
  for (const contact::IslandRow& r : c.irows)
    cold = cold && r.pn == 0.0;
  contact::solve_island(c.ibodies, c.irows, cold ? 5000 : 500, 1e-7);
  // The forces for the next step's warm start.
  {
    std::size_t row = 0;
    for (int k = 0; k < nt; ++k) {
      const detail::IslandContact& t = touching[k];
      detail::WarmContact wc;
      wc.a = t.a, wc.b = t.b, wc.part = t.part, wc.np = t.np;
      const contact::Pose pa = pose_of(t.a);
      for (int i = 0; i < t.np; ++i, ++row) {
        const contact::IslandRow& r = c.irows[row];
        wc.p_B[i] = pa.q_WB.conjugate() * (t.p[i] - pa.p_WBo);
        wc.f_W[i] = (r.pn * r.n + r.pt.x() * r.t1 + r.pt.y() * r.t2) / h;
      }
      c.next_warm.push_back(wc);  // within its reserve while contacts stay few a body
    }
  }
  // The impulses as constant forces over h, per body.
  for (std::size_t k = 0; k < ids.size(); ++k) {
    Vec3 F = Vec3::Zero(), tau = Vec3::Zero();
    for (const contact::IslandRow& r : c.irows) {
      const Vec3 P = r.pn * r.n + r.pt.x() * r.t1 + r.pt.y() * r.t2;
      if (r.a == static_cast<int>(k)) F += P, tau += r.r_a.cross(P);
      if (r.b == static_cast<int>(k)) F -= P, tau -= r.r_b.cross(P);
    }
    with_moving(ids[k], [&](contact::MovingBody& B) {
      B.plan(h, contact::SupportLoad{F / h, tau / h});
      B.advance(h);
    });
  }
  // Overlap left over taken back: each contact's bodies moved apart along its normal, by their
  // shares of inverse mass (a part does not move).
  for (int sweep = 0; sweep < 3; ++sweep) {
    for (int k = 0; k < nt; ++k) {
      const detail::IslandContact& t = touching[k];
      double depth;
      Vec3 n;
      if (t.b >= 0) {
        const contact::PairGap g = contact::pair_gap(cm.shapes[cm.shape_of[t.a]], pose_of(t.a),
                                                     cm.shapes[cm.shape_of[t.b]], pose_of(t.b));
        depth = -g.distance, n = g.n_W;
      } else {
        const contact::Gap g =
            contact::gap(cm.shapes[cm.shape_of[t.a]], pose_of(t.a), cm.parts[t.part]);
        depth = -g.distance, n = g.n_W;
      }
      if (depth <= kSlop) continue;
      const double wa = c.ibodies[c.ilocal[t.a]].resp.inv_m.maxCoeff();
      const double wb = t.b >= 0 ? c.ibodies[c.ilocal[t.b]].resp.inv_m.maxCoeff() : 0.0;
      if (wa + wb <= 0.0) continue;
      const double push = depth - kSlop;
      with_moving(t.a, [&](contact::MovingBody& B) { B.shift(push * wa / (wa + wb) * n); });
      if (t.b >= 0)
        with_moving(t.b, [&](contact::MovingBody& B) { B.shift(-push * wb / (wa + wb) * n); });
    }
  }
  // Under gravity alone the island's energy may not rise (the moves out of overlap, the forces
  // held over a turning body): the excess comes out of its kinetic energy.
  if (conservative) {
    double e_end = 0.0, ke = 0.0;
    for (const int id : ids) {
      with_moving(id, [&](contact::MovingBody& B) {
        e_end += B.energy();
        ke += B.kinetic_energy();
      });
    }
    const double excess = e_end - e_start;
    if (excess > 0.0 && ke > 0.0) {
      const double scale = std::sqrt(std::max(0.0, 1.0 - excess / ke));
      for (const int id : ids) {
        with_moving(id, [&](contact::MovingBody& B) {
          const contact::MotionSample m = B.state();
          B.set_velocity(scale * m.v_W, scale * m.w_W);
        });
      }
    }
  }
  // Impacts among them: contacts that closed in from apart.
  for (int k = 0; k < nt; ++k) {
    const detail::IslandContact& t = touching[k];
    if (t.gap <= kSlop) continue;
    Vec3 J = Vec3::Zero(), centre = Vec3::Zero();
    int rows_before = 0;
    for (int j = 0; j < k; ++j)
      rows_before += touching[j].np;
    for (int i = 0; i < t.np; ++i) {
      const contact::IslandRow& r = c.irows[static_cast<std::size_t>(rows_before + i)];
      J += r.pn * r.n + r.pt.x() * r.t1 + r.pt.y() * r.t2;
      centre += t.p[i] / t.np;
    }
    if (J.isZero(0)) continue;
    ContactEvent e;
    e.kind = ContactEventKind::kImpact;
    e.body = t.a;
    e.part = t.part;
    e.other = t.b;
    e.time = time;
    e.p_W = centre;
    e.n_W = t.n;
    e.impulse_W = J;
    push_event(e);
  }
}

// Rows [first, first + t.np) of contact t start from the forces its points carried in the last
// step: each point takes the force of the last step's point nearest to it on body a, if one lies
// within a hundredth of the body's size, as the impulse over h (the tangential part in the row's
// own tangents, made by the solve: given here as the world vector's components).
void World::Impl::warm_start(const detail::IslandContact& t, double h, std::size_t first) {
  detail::ContactData& c = data.contact;
  const auto key = std::tuple(t.a, t.b, t.part);
  const auto it =
      std::lower_bound(c.warm.begin(), c.warm.end(), key,
                       [](const detail::WarmContact& w, const auto& k) { return w.key() < k; });
  if (it == c.warm.end() || it->key() != key) return;
  const detail::ContactModel& cm = model().contact;
  const contact::Pose pa = pose_of(t.a);
  const double near = 1e-2 * cm.shapes[cm.shape_of[t.a]].bounding_radius();
  for (int i = 0; i < t.np; ++i) {
    const Vec3 p_B = pa.q_WB.conjugate() * (t.p[i] - pa.p_WBo);
    int best = -1;
    double d = near;
    for (int j = 0; j < it->np; ++j) {
      const double dj = (it->p_B[j] - p_B).norm();
      if (dj <= d) d = dj, best = j;
    }
    if (best < 0) continue;
    contact::IslandRow& r = c.irows[first + static_cast<std::size_t>(i)];
    const Vec3 P = h * it->f_W[best];
    r.pn = std::max(0.0, P.dot(r.n));
    // The row's tangents are made in the solve from n; the same construction here.
    Vec3 t1, t2;
    const Vec3& n = r.n;
    const double sign = std::copysign(1.0, n.z());
    const double aa = -1.0 / (sign + n.z());
    const double bb = n.x() * n.y() * aa;
    t1 = Vec3(1.0 + sign * n.x() * n.x() * aa, sign * bb, -sign * n.x());
    t2 = Vec3(bb, sign + n.y() * n.y() * aa, -n.y());
    r.pt = Eigen::Vector2d(P.dot(t1), P.dot(t2));
    const double limit = r.mu * r.pn;
    if (r.pt.norm() > limit) r.pt *= r.pt.norm() > 0.0 ? limit / r.pt.norm() : 0.0;
  }
}

void World::Impl::push_event(const ContactEvent& e) {
  detail::ContactData& c = data.contact;
  if (static_cast<int>(c.events.size()) < detail::kMaxContactEvents) {
    c.events.push_back(e);  // within the reserved capacity
  } else {
    ++c.dropped;
  }
}

}  // namespace rigid::physics
