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
  b.q = b.q * quat_exp(s * b.w);
  renormalize(b.q);
}
inline void drift(AxiGroup& g, int i, double s) {
  Motion& b = g.motion[i];
  const DiagRot& r = g.rot[i];
  Vec3 mom = r.I.cwiseProduct(b.w);
  AxisymPlan p;
  make_axisym_plan(r.I.x(), r.I.z(), mom, s, p);
  Quat dq;
  advance_axisym(p, mom, dq);
  b.q = b.q * dq;
  renormalize(b.q);
  b.w = r.inv_I.cwiseProduct(mom);
}
inline void drift(GenGroup& g, int i, double s) {
  Motion& b = g.motion[i];
  const DiagRot& r = g.rot[i];
  Vec3 mom = r.I.cwiseProduct(b.w);
  Quat dq;
  free_rotor_step(g.rotor[i], mom, s, dq);
  b.q = b.q * dq;
  renormalize(b.q);
  b.w = r.inv_I.cwiseProduct(mom);
}

// Exact rotation over the model's dt, reusing the cached plan while the momentum is untouched.
inline void drift_cached(IsoGroup& g, int i, double h) {
  Motion& b = g.motion[i];
  if (!g.dq_ok[i]) {
    g.dq[i] = quat_exp(h * b.w);
    g.dq_ok[i] = 1;
  }
  b.q = b.q * g.dq[i];
  renormalize(b.q);
}
inline void drift_cached(AxiGroup& g, int i, double h) {
  Motion& b = g.motion[i];
  const DiagRot& r = g.rot[i];
  Vec3 mom = r.I.cwiseProduct(b.w);
  if (!g.plan_ok[i]) {
    make_axisym_plan(r.I.x(), r.I.z(), mom, h, g.plan[i]);
    g.plan_ok[i] = 1;
  }
  Quat dq;
  advance_axisym(g.plan[i], mom, dq);
  b.q = b.q * dq;
  renormalize(b.q);
  b.w = r.inv_I.cwiseProduct(mom);
}
inline void drift_cached(GenGroup& g, int i, double h) {
  Motion& b = g.motion[i];
  const DiagRot& r = g.rot[i];
  Vec3 mom = r.I.cwiseProduct(b.w);
  if (!g.plan_ok[i]) {
    make_rotor_plan(g.rotor[i], mom, h, g.plan[i]);
    g.plan_ok[i] = 1;
  }
  Quat dq;
  advance_rotor(g.plan[i], mom, dq);
  b.q = b.q * dq;
  renormalize(b.q);
  b.w = r.inv_I.cwiseProduct(mom);
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
    const Vec3 a = lin.accel(g.loads[i].force_W(b.q));
    translate(m.tc(lin, kFull), a, a, b.x, b.v);
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
    if (L.torque_free() && L.orientation_free_force() && rot.k == 0.0) {
      const Vec3 a = lin.accel(L.f_W);
      translate(m.tc(lin, kFull), a, a, b.x, b.v);
      drift_cached(g, i, h);
      continue;
    }
    invalidate(g, i);
    const Vec3 rates = rot.drag_rates();
    // First-same-as-last: the loads at the end of a stage are those at the start of the next.
    Vec3 a0 = lin.accel(L.force_W(b.q));
    Vec3 alpha0 = rot.alpha(L.torque_P(b.q));
    const auto stage = [&](double s, TransSize size) {
      kick_angular(alpha0, rates, 0.5 * s, b.w);
      drift(g, i, s);
      const Vec3 a1 = lin.accel(L.force_W(b.q));
      const Vec3 alpha1 = rot.alpha(L.torque_P(b.q));
      translate(m.tc(lin, size), a0, a1, b.x, b.v);
      kick_angular(alpha1, rates, 0.5 * s, b.w);
      a0 = a1;
      alpha0 = alpha1;
    };
    if (fourth_order) {
      for (int k = 0; k < Composition::kStages; ++k) {
        stage(Composition::kStage[k] * h, Composition::kSize[k]);
      }
    } else {
      stage(h, kFull);
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
