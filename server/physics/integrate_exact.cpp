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
#include <type_traits>

#include "physics/kernels.hpp"

namespace rigid::physics::detail {

namespace {

// Exact rotation over s, no cache.
inline void drift(IsoGroup& g, int i, double s) {
  Motion& b = g.motion[i];
  b.q = b.q * quat_exp(s * b.spin);
  renormalize(b.q);
}
inline void drift(AxiGroup& g, int i, double s) {
  Motion& b = g.motion[i];
  const DiagRot& r = g.rot[i];
  AxisymPlan p;
  make_axisym_plan(r.I.x(), r.I.z(), b.spin, s, p);
  Quat dq;
  advance_axisym(p, b.spin, dq);
  b.q = b.q * dq;
  renormalize(b.q);
}
inline void drift(GenGroup& g, int i, double s) {
  Motion& b = g.motion[i];
  Quat dq;
  free_rotor_step(g.rotor[i], b.spin, s, dq);
  b.q = b.q * dq;
  renormalize(b.q);
}

// Exact rotation over the model's dt, reusing the cached plan while the momentum is untouched.
inline void drift_cached(IsoGroup& g, int i, double h) {
  Motion& b = g.motion[i];
  if (!g.dq_ok[i]) {
    g.dq[i] = quat_exp(h * b.spin);
    g.dq_ok[i] = 1;
  }
  b.q = b.q * g.dq[i];
  renormalize(b.q);
}
inline void drift_cached(AxiGroup& g, int i, double h) {
  Motion& b = g.motion[i];
  const DiagRot& r = g.rot[i];
  if (!g.plan_ok[i]) {
    make_axisym_plan(r.I.x(), r.I.z(), b.spin, h, g.plan[i]);
    g.plan_ok[i] = 1;
  }
  Quat dq;
  advance_axisym(g.plan[i], b.spin, dq);
  b.q = b.q * dq;
  renormalize(b.q);
}
inline void drift_cached(GenGroup& g, int i, double h) {
  Motion& b = g.motion[i];
  if (!g.plan_ok[i]) {
    make_rotor_plan(g.rotor[i], b.spin, h, g.plan[i]);
    g.plan_ok[i] = 1;
    g.axis[i] = Quat(0.0, 0.0, 0.0, 0.0);
  }
  Quat dq;
  advance_rotor(g.plan[i], b.spin, dq, RotorUpdate::kPinned, &g.axis[i]);
  b.q = b.q * dq;
  renormalize(b.q);
}

inline void invalidate(IsoGroup& g, int i) {
  g.dq_ok[i] = 0;
}
inline void invalidate(AxiGroup& g, int i) {
  g.plan_ok[i] = 0;
}
inline void invalidate(GenGroup& g, int i) {
  g.plan_ok[i] = 0;
}

void exact_points(PointGroup& g, const Model& m) {
  // A point mass never turns: its acceleration is constant over the step, so this is exact.
  for (int i = 0; i < g.size(); ++i) {
    Motion& b = g.motion[i];
    const Linear& lin = g.linear[i];
    translate(m.tc(lin, kFull), lin.accel(g.loads[i].force_W(b.q)), b.x, b.v);
  }
}

template <class G>
void exact_group(G& g, const Model& m, bool fourth_order) {
  const double h = m.dt;
  for (int i = 0; i < g.size(); ++i) {
    Motion& b = g.motion[i];
    const Linear& lin = g.linear[i];
    const Loads& L = g.loads[i];
    const auto& rot = g.rot[i];
    if (L.quiet()) {
      translate(m.tc(lin, kFull), lin.accel(L.f_W), b.x, b.v);
      drift_cached(g, i, h);
      continue;
    }
    invalidate(g, i);
    const Vec3 rates = rot.drag_rates();
    // Stages s_1..s_n (one for exact_rotor, Suzuki's five for exact_rotor4). The closing half kick
    // of a stage and the opening half kick of the next act at the same orientation with the same
    // loads, and the kick flow is a one-parameter group: they are merged into one kick of
    // (s_k + s_k+1) / 2. Fewer additions of small increments to w, less round-off, less work.
    const int n = fourth_order ? Composition::kStages : 1;
    const auto size_of = [&](int k) { return fourth_order ? Composition::kStage[k] * h : h; };
    Vec3 a0 = lin.accel(L.force_W(b.q));
    Vec3 rate = rot.spin_rate(L.torque_P(b.q));
    kick_angular(rate, rates, 0.5 * size_of(0), b.spin);
    for (int k = 0; k < n; ++k) {
      const double s = size_of(k);
      drift(g, i, s);
      const Vec3 a1 = lin.accel(L.force_W(b.q));
      rate = rot.spin_rate(L.torque_P(b.q));
      translate(m.tc(lin, fourth_order ? Composition::kSize[k] : kFull), a0, a1, b.x, b.v);
      const double next = k + 1 < n ? size_of(k + 1) : 0.0;
      kick_angular(rate, rates, 0.5 * (s + next), b.spin);
      a0 = a1;
    }
  }
}

}  // namespace

void step_exact(Model& m, bool fourth_order) {
  exact_points(m.point, m);
  exact_group(m.iso, m, fourth_order);
  exact_group(m.axi, m, fourth_order);
  exact_group(m.gen, m, fourth_order);
}

}  // namespace rigid::physics::detail
