// Splitting with the exact free rotor as its drift (Celledoni, Fasso, Safstrom & Zanna 2008):
//   S(h) = kick(h/2) . drift(h) . kick(h/2)
//     kick:  w_P += h/2 I^-1 tau_P(q)            (angular drag as an exact decay)
//     drift: (q, m_P) <- the exact torque-free motion over h (free_rotor.hpp)
//   with the translation done by the exact drag flow with the acceleration interpolated linearly
//   between the orientations at both ends (translation.hpp).
// S is symmetric and second order, symplectic for conservative loads, and exact whenever the body
// carries no torque. exact_rotor4 composes S into fourth order (Suzuki's five stages, model.hpp).
//
// A body with no torque, no angular drag and no force that turns with it is integrated exactly by
// one drift and one exact translation, whatever the order asked for: its rotation plan (elliptic
// constants and quadrature nodes for this h) is cached until something changes its momentum.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include "physics/hybrid_lanes.hpp"
#include "physics/iso_lanes.hpp"
#include "physics/kernels.hpp"
#include "physics/rotor_lanes.hpp"
#include "physics/translation_lanes.hpp"

namespace rigid::physics::detail {

namespace {

// Exact rotation over s, no cache.
inline void drift(SteadySpinGroup g, int i, double s) {
  Motion& b = g.motion(i);
  b.q = b.q * quat_exp(s * b.spin);
  renormalize(b.q);
}
inline void drift(PrecessionGroup g, int i, double s) {
  Motion& b = g.motion(i);
  const DiagRot& r = g.rot(i);
  AxisymPlan p;
  make_axisym_plan(r.I.x(), r.I.z(), b.spin, s, p);
  Quat dq;
  advance_axisym(p, b.spin, dq);
  b.q = b.q * dq;
  renormalize(b.q);
}
inline void drift(TumblingGroup g, int i, double s) {
  Motion& b = g.motion(i);
  Quat dq;
  free_rotor_step(g.rotor(i), b.spin, s, dq);
  b.q = b.q * dq;
  renormalize(b.q);
}

// The caches of the exact drift over h for entry i's momentum as it is now: what the quiet run
// reuses until something changes the momentum (invalidate). The step makes them where they are
// stale, and so does fill_quiet_caches, with these same functions: a cache made ahead is the one
// the step would have made.
inline void make_increment(SteadySpinGroup g, int i, double h) {
  g.entries.plan.set(i, quat_exp(h * g.motion(i).spin));
  g.entries.plan_ok[i] = 1;
}
inline void make_plan(PrecessionGroup g, int i, double h) {
  const DiagRot& r = g.rot(i);
  make_axisym_plan(r.I.x(), r.I.z(), g.motion(i).spin, h, g.entries.plan[i]);
  g.entries.plan_ok[i] = 1;
}
// Also gives the whole plan, which the store keeps only in part (rotor_plans.hpp).
inline void make_plan(TumblingGroup g, int i, double h, RotorPlan& plan) {
  make_rotor_plan(g.rotor(i), g.motion(i).spin, h, plan);
  g.entries.plan.set(i, plan);
  g.entries.plan_ok[i] = 1;
}

// Exact rotation over the model's dt, reusing the cached plan while the momentum is untouched.
inline void drift_cached(PrecessionGroup g, int i, double h) {
  Motion& b = g.motion(i);
  if (!g.entries.plan_ok[i]) make_plan(g, i, h);
  Quat dq;
  advance_axisym(g.entries.plan[i], b.spin, dq);
  b.q = b.q * dq;
  renormalize(b.q);
}
inline void drift_cached(TumblingGroup g, int i, double h) {
  Motion& b = g.motion(i);
  RotorPlan plan;
  if (!g.entries.plan_ok[i]) {
    make_plan(g, i, h, plan);
  } else {
    plan = g.entries.plan.get(i);
  }
  Quat dq;
  advance_rotor(plan, b.spin, dq, RotorUpdate::kPinned);
  b.q = b.q * dq;
  renormalize(b.q);
}

// The cached drift of entry i is stale: its momentum changes.
template <class G>
inline void invalidate(G g, int i) {
  g.entries.plan_ok[i] = 0;
}

// The translations of the quiet entries [begin, end) (translate with the force f_W alone): runs
// of entries sharing their parameters through the kernel of the World's width
// (translation_lanes.hpp), one vector a body; the scalar code when the World has no such kernel
// (width 2, or 1 in tests). Both give the same bits.
template <class G>
void translate_quiet(G g, const Model& m, int begin, int end) {
  if (m.lanes < 4) {
    LinearCursor c(g, m, kFull);
    for (int i = begin; i < end; ++i) {
      Motion& b = g.motion(i);
      c.at(i);
      translate(c.tc(), c.lin().accel(g.entries.loads[i].f_W), b.x, b.v);
    }
    return;
  }
  // The kernel reads v (and keeps the double after it) from x's address on.
  static_assert(sizeof(Vec3) == 3 * sizeof(double));
  static_assert(std::is_standard_layout_v<Motion> &&
                offsetof(Motion, v) == offsetof(Motion, x) + 24 &&
                offsetof(Motion, spin) == offsetof(Motion, v) + 24);
  const std::int32_t* rows = g.entries.linear.data();
  for (int i = begin; i < end;) {
    const std::int32_t k = rows[i];
    int j = i + 1;
    // Eight indices at a time (a loop the compiler vectorises) while they all match, then one by
    // one.
    for (; j + 8 <= end; j += 8) {
      std::int32_t differ = 0;
      for (int l = 0; l < 8; ++l)
        differ |= rows[j + l] ^ k;
      if (differ != 0) break;
    }
    while (j < end && rows[j] == k)
      ++j;
    const Linear& lin = g.params.linear[k];
    const TransCoef& tc = m.tc(lin, kFull);
    const SharedTranslation st{{lin.g.x(), lin.g.y(), lin.g.z()},
                               {lin.inv_m.x(), lin.inv_m.y(), lin.inv_m.z()},
                               tc.E,
                               tc.p1,
                               tc.q2};
    char* x = reinterpret_cast<char*>(g.motion(i).x.data());
    // No force in W on any quiet body of the group: the kernel reads none (Entries::quiet_pushed).
    const char* f = g.entries.quiet_pushed == 0
                        ? nullptr
                        : reinterpret_cast<const char*>(g.entries.loads[i].f_W.data());
    if (m.lanes == 8) {
      lanes8::translate_quiet(x, sizeof(Motion), f, sizeof(LoadHead), st, j - i);
    } else {
      lanes4::translate_quiet(x, sizeof(Motion), f, sizeof(LoadHead), st, j - i);
    }
    i = j;
  }
}

// The translation group never turns: its acceleration is constant over the step, so this is exact.
// The quiet run's force is f_W alone (translate_quiet); the loaded run's may turn with the body.
void exact_translation(TranslationGroup g, const Model& m, const Range (&run)[2]) {
  translate_quiet(g, m, run[0].begin, run[0].end);
  LinearCursor c(g, m, kFull);
  for (int i = run[1].begin; i < run[1].end; ++i) {
    Motion& b = g.motion(i);
    c.at(i);
    translate(c.tc(), c.lin().accel(g.load(i).force_W(b.q)), b.x, b.v);
  }
}

// Bodies with nothing turning them: one exact translation and one exact drift, the rotation plan
// cached until something changes the momentum. Body by body: the axisymmetric and general drifts
// are long enough to hide the translation's memory traffic behind them, and splitting them into
// passes (translate_quiet first) was slower at 10^6 axisymmetric bodies and no faster at 10^3
// (bench/notes/step-kernels.md, "Point masses and spheres").
template <class G>
void exact_quiet(G g, const Model& m, Range r) {
  const double h = m.dt;
  LinearCursor c(g, m, kFull);
  for (int i = r.begin; i < r.end; ++i) {
    Motion& b = g.motion(i);
    c.at(i);
    translate(c.tc(), c.lin().accel(g.entries.loads[i].f_W), b.x, b.v);
    drift_cached(g, i, h);
  }
}

// exact_quiet for the steady-spin group, whose step is a few operations: a chunk at a time, the
// translations first (translate_quiet), then the rotations, four at a time with the kernel of the
// World's width (iso_lanes.hpp) and one by one for the rest. Small chunks: the bodies stay in L1
// between the passes. Bodies are independent and each path gives the same bits, so neither the
// split nor the route changes a result. Every increment is made before any is applied: the order
// of the scalar code per body.
constexpr int kQuietChunk = 32;  // a multiple of 4 (IncrementBlock)
// Entries [from, to) turned by their cached increments, one by one.
void apply_increments(SteadySpinGroup g, int from, int to) {
  for (int i = from; i < to; ++i) {
    Motion& b = g.motion(i);
    b.q = b.q * g.entries.plan.get(i);
    renormalize(b.q);
  }
}
void exact_quiet(SteadySpinGroup g, const Model& m, Range r) {
  const double h = m.dt;
  for (int begin = r.begin; begin < r.end; begin += kQuietChunk) {
    const int end = std::min(begin + kQuietChunk, r.end);
    translate_quiet(g, m, begin, end);
    for (int i = begin; i < end; ++i) {
      // Eight flags at a time: after the first step they are almost always all set.
      if (i % 8 == 0 && i + 8 <= end) {
        std::uint64_t flags;
        std::memcpy(&flags, &g.entries.plan_ok[i], sizeof flags);
        if (flags == 0x0101010101010101u) {
          i += 7;
          continue;
        }
      }
      if (!g.entries.plan_ok[i]) make_increment(g, i, h);
    }
    // The kernel takes whole blocks of increments: the bodies before the first block boundary
    // (none when the range starts on one, as the quiet runs' slices do) and after the last take
    // the scalar code.
    const auto scalar = [&](int from, int to) { apply_increments(g, from, to); };
    int i = begin;
    if (m.lanes >= 4) {
      const int first = std::min((begin + 3) / 4 * 4, end);
      scalar(begin, first);
      static_assert(sizeof(Quat) == 4 * sizeof(double));
      const int n = (end - first) / 4 * 4;
      if (n > 0) {
        char* q = reinterpret_cast<char*>(g.motion(first).q.coeffs().data());
        if (m.lanes == 8) {
          lanes8::iso_drift(q, sizeof(Motion), g.entries.plan.block(first), n);
        } else {
          lanes4::iso_drift(q, sizeof(Motion), g.entries.plan.block(first), n);
        }
      }
      i = first + n;
    }
    scalar(i, end);
  }
}

// exact_quiet for the tumbling group, its rotation eight at once (rotor_lanes.hpp): a block of
// eight entries (rotor_plans.hpp) inside the range whose cached plans can all step in the kernel
// is stepped from its block; the others (a plan to make, a still body, a long step, a block cut
// by the range's ends) take the scalar path. Both give the same bits, so the route a body takes
// depends on nothing but its own plan and place. The translation does not depend on the rotation
// of a body with nothing turning it: as for the steady-spin group, a chunk's translations go first
// (translate_quiet, which reads no loads when no quiet body is pushed), then its rotations; the
// chunks end on block boundaries, so they cut no block that the range does not.
void exact_quiet_lanes(TumblingGroup g, const Model& m, Range r) {
  const int width = m.lanes;
  if (width == 1) return exact_quiet(g, m, r);
  constexpr int kBlock = RotorPlans::kBlock;
  static_assert(kQuietChunk % kBlock == 0);
  RotorStateLanes st;
  for (int begin = r.begin; begin < r.end;) {
    const int end = std::min(r.end, (begin / kBlock) * kBlock + kQuietChunk);
    translate_quiet(g, m, begin, end);
    for (int i = begin; i < end;) {
      const bool whole = i % kBlock == 0 && i + kBlock <= end && rotor_block_ready(g, i / kBlock);
      if (whole) {
        g.entries.plan.prefetch(i / kBlock + 2);
        rotor_gather_block(g, i / kBlock, st);
        rotor_step_lanes(width, st, g.entries.plan.lanes(i / kBlock),
                         g.entries.plan.flags(i / kBlock));
        rotor_scatter_block(st, i / kBlock, g);
        i += kBlock;
      } else {
        drift_cached(g, i, m.dt);
        ++i;
      }
    }
    begin = end;
  }
}

// The composition of kick-drift-kick stages S(c_k h), k = 1..n, for one body, with the stage's
// drift given by `drift(i, s)` (exact or split free rotor). The closing half kick of a stage and
// the opening half kick of the next act at the same orientation with the same loads, and the kick
// flow is a one-parameter group: they are merged into one kick of (s_k + s_k+1) / 2. Fewer
// additions of small increments to w, less round-off, less work.
template <class Comp, class G, class Drift>
[[gnu::flatten]] inline void compose_loaded(G g, const Model& m, int i, Drift&& drift) {
  const double h = m.dt;
  Motion& b = g.motion(i);
  const Linear& lin = g.linear(i);
  const LoadsRef L = g.load(i);
  const auto& rot = g.rot(i);
  const Vec3 rates = rot.drag_rates();
  Vec3 a0 = lin.accel(L.force_W(b.q));
  Vec3 rate = rot.spin_rate(L.torque_P(b.q));
  kick_angular(rate, rates, 0.5 * Comp::kStage[0] * h, b.spin);
  for (int k = 0; k < Comp::kStages; ++k) {
    const double s = Comp::kStage[k] * h;
    drift(i, s);
    const Vec3 a1 = lin.accel(L.force_W(b.q));
    rate = rot.spin_rate(L.torque_P(b.q));
    translate(m.tc(lin, Comp::kSize[k]), a0, a1, b.x, b.v);
    const double next = k + 1 < Comp::kStages ? Comp::kStage[k + 1] * h : 0.0;
    kick_angular(rate, rates, 0.5 * (s + next), b.spin);
    a0 = a1;
  }
}

// exact_rotor: the splitting itself, one stage.
struct OneStage {
  static constexpr int kStages = 1;
  static constexpr double kStage[1] = {1.0};
  static constexpr TransSize kSize[1] = {kFull};
};

// exact_rotor / exact_rotor4: the quiet run takes the exact free step (tumbling bodies over lanes,
// as hybrid4's), the loaded run the composition with exact drifts.
template <class G>
void exact_loaded(G g, const Model& m, bool fourth_order, Range r) {
  for (int i = r.begin; i < r.end; ++i) {
    invalidate(g, i);
    const auto exact = [g](int j, double s) { drift(g, j, s); };
    if (fourth_order) {
      compose_loaded<Composition>(g, m, i, exact);
    } else {
      compose_loaded<OneStage>(g, m, i, exact);
    }
  }
}

// --- hybrid4: the exact free rotor for quiet bodies, a cheap fourth-order step for loaded ones ---

// Exact flow over t of the sub-Hamiltonian d m_a^2 / 2 (a principal axis a of P): the body turns
// about its axis a by theta = t d m_a, and m turns the other way about it (m' = m x (d m_a e_a)),
// m_a unchanged.
inline void axis_turn(int a, double d, double t, Vec3& m, Quat& q) {
  const double theta = t * d * m[a];
  double ch, sinc;
  cos_sinc(0.5 * theta, ch, sinc);
  const double sh = 0.5 * theta * sinc;
  const double c = ch * ch - sh * sh, sn = 2.0 * ch * sh;
  const int j = (a + 1) % 3, k = (a + 2) % 3;
  const double mj = m[j], mk = m[k];
  m[j] = c * mj + sn * mk;
  m[k] = -sn * mj + c * mk;
  Quat e(ch, 0.0, 0.0, 0.0);
  e.vec()[a] = sh;
  q = q * e;
}

// The axisymmetric free rotor, moments (A, A, C) about P's z axis, a = 1/A, c = 1/C, in closed form
// (Landau & Lifshitz section 33): with H = a |m|^2 / 2 + (c - a) m3^2 / 2, whose two terms commute
// (|m|^2 is a Casimir), q <- q exp(s a m) exp(s (c - a) m3 z) and m turns by -s (c - a) m3 about z.
// The half angles come from their squares (cos_sinc_sq: no square root, no libm while small).
inline void axisym_turn(double a, double c, double s, Vec3& m, Quat& q) {
  double cw, sw;
  const double hs = 0.5 * s * a;
  cos_sinc_sq(hs * hs * m.squaredNorm(), cw, sw);
  sw *= hs;  // exp(s a m / 2 ...) = (cw, sw m)
  const double phi = s * (c - a) * m.z();
  double cz, sz;
  cos_sinc_sq(0.25 * phi * phi, cz, sz);
  sz *= 0.5 * phi;  // exp(phi z / 2) = (cz, sz z)
  const double c2 = cz * cz - sz * sz, s2 = 2.0 * cz * sz;
  // dq = (cw, sw m) (cz, sz z)
  const Quat dq(cw * cz - sw * m.z() * sz, sw * (m.x() * cz + m.y() * sz),
                sw * (m.y() * cz - m.x() * sz), cw * sz + sw * m.z() * cz);
  q = q * dq;
  const double m1 = m.x(), m2 = m.y();
  m.x() = c2 * m1 + s2 * m2;
  m.y() = -s2 * m1 + c2 * m2;
}

// The split free rotor of a general body (moments I1 < I2 < I3 in P, a_i = 1 / I_i):
//   H = m.m a2 / 2 + (a1 - a2) m1^2 / 2 + (a3 - a2) m3^2 / 2
//     = [axisymmetric rotor of moments (I2, I2, I3)] + [(a1 - a2) m1^2 / 2],
// the Casimir |m|^2 taken with the middle moment so that the two non-commuting parts are the
// smallest possible, (a1 - a2)(a2 - a3) (Touma & Wisdom, "Lie-Poisson integrators for rigid body
// dynamics in the solar system", Astron. J. 107 (1994), symmetric top + correction). Each part is
// exact and cheap (closed-form precession, an axis turn); the drift X1(s/2) A(s) X1(s/2) is
// symmetric, second order in s, and exact for an axisymmetric body.
inline void split_drift(TumblingGroup g, int i, double s) {
  Motion& b = g.motion(i);
  const Vec3& a = g.rot(i).inv_I;
  const double d1 = a.x() - a.y();
  axis_turn(0, d1, 0.5 * s, b.spin, b.q);
  axisym_turn(a.y(), a.z(), s, b.spin, b.q);
  axis_turn(0, d1, 0.5 * s, b.spin, b.q);
  renormalize(b.q);
}
inline void fast_drift(PrecessionGroup g, int i, double s) {
  Motion& b = g.motion(i);
  axisym_turn(g.rot(i).inv_I.x(), g.rot(i).inv_I.z(), s, b.spin, b.q);
  renormalize(b.q);
}
inline void fast_drift(SteadySpinGroup g, int i, double s) {
  drift(g, i, s);
}
inline void fast_drift(TumblingGroup g, int i, double s) {
  split_drift(g, i, s);
}

template <class Comp, class G>
void hybrid_loaded(G g, const Model& m, Range r) {
  for (int i = r.begin; i < r.end; ++i) {
    invalidate(g, i);
    compose_loaded<Comp>(g, m, i, [g](int j, double s) { fast_drift(g, j, s); });
  }
}

// The default (TripleJump) steps the loaded precession and tumbling bodies several at once
// (hybrid_lanes.hpp); the steady-spin ones, every loaded body of the Suzuki candidate, and all of
// them with m.lanes == 1 (the scalar reference), one by one.
template <class Comp>
void step_hybrid_with(const Model& m, Data& d, Share& sh) {
  const TranslationGroup translation = group(m, d, kTranslationGroup);
  const SteadySpinGroup spin = group(m, d, kSteadySpinGroup);
  const PrecessionGroup precession = group(m, d, kPrecessionGroup);
  const TumblingGroup tumbling = group(m, d, kTumblingGroup);
  exact_translation(translation, m, sh.run[translation.kIndex]);
  exact_quiet(spin, m, sh.run[spin.kIndex][0]);
  hybrid_loaded<Comp>(spin, m, sh.run[spin.kIndex][1]);
  exact_quiet(precession, m, sh.run[precession.kIndex][0]);
  exact_quiet_lanes(tumbling, m, sh.run[tumbling.kIndex][0]);
  if (std::is_same_v<Comp, TripleJump> && m.lanes > 1) {
    hybrid_loaded_lanes(precession, m, sh.run[precession.kIndex][1]);
    hybrid_loaded_lanes(tumbling, m, sh.run[tumbling.kIndex][1]);
  } else {
    hybrid_loaded<Comp>(precession, m, sh.run[precession.kIndex][1]);
    hybrid_loaded<Comp>(tumbling, m, sh.run[tumbling.kIndex][1]);
  }
}

}  // namespace

void step_exact(const Model& m, Data& d, bool fourth_order, Share& sh) {
  const TranslationGroup translation = group(m, d, kTranslationGroup);
  const SteadySpinGroup spin = group(m, d, kSteadySpinGroup);
  const PrecessionGroup precession = group(m, d, kPrecessionGroup);
  const TumblingGroup tumbling = group(m, d, kTumblingGroup);
  exact_translation(translation, m, sh.run[translation.kIndex]);
  exact_quiet(spin, m, sh.run[spin.kIndex][0]);
  exact_loaded(spin, m, fourth_order, sh.run[spin.kIndex][1]);
  exact_quiet(precession, m, sh.run[precession.kIndex][0]);
  exact_loaded(precession, m, fourth_order, sh.run[precession.kIndex][1]);
  exact_quiet_lanes(tumbling, m, sh.run[tumbling.kIndex][0]);
  exact_loaded(tumbling, m, fourth_order, sh.run[tumbling.kIndex][1]);
}

void fill_quiet_caches(const Model& m, Data& d, Share& sh) {
  const double h = m.dt;
  std::int64_t made = 0;
  const SteadySpinGroup spin = group(m, d, kSteadySpinGroup);
  const Range rs = sh.run[spin.kIndex][0];
  for (int i = rs.begin; i < rs.end; ++i) {
    if (spin.entries.plan_ok[i]) continue;
    make_increment(spin, i, h);
    ++made;
  }
  const PrecessionGroup precession = group(m, d, kPrecessionGroup);
  const Range rp = sh.run[precession.kIndex][0];
  for (int i = rp.begin; i < rp.end; ++i) {
    if (precession.entries.plan_ok[i]) continue;
    make_plan(precession, i, h);
    ++made;
  }
  const TumblingGroup tumbling = group(m, d, kTumblingGroup);
  const Range rt = sh.run[tumbling.kIndex][0];
  RotorPlan plan;
  for (int i = rt.begin; i < rt.end; ++i) {
    if (tumbling.entries.plan_ok[i]) continue;
    make_plan(tumbling, i, h, plan);
    ++made;
  }
  sh.caches_made = made;
}

void step_hybrid(const Model& m, Data& d, Share& sh, int variant) {
  if (variant == 0) {
    step_hybrid_with<TripleJump>(m, d, sh);
  } else {
    step_hybrid_with<Composition>(m, d, sh);
  }
}

}  // namespace rigid::physics::detail
