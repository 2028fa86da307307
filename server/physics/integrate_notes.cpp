// The course notes' schemes, reproduced as the notes write them (GAMES103 "Rigid Body Dynamics",
// slides "Translational Motion", "Leapfrog Integration", "Rigid Body Simulation: Implementation"):
//   translation: explicit Euler, semi-implicit Euler, midpoint or leapfrog; drag as the force -c v;
//   rotation:    w += dt I^-1 tau with I = R I_ref R^T, q += [0, dt/2 w] x q, then normalise,
//                w being the world-frame angular velocity.
// The rotation update has no gyroscopic term: for a body whose principal moments differ it keeps
// w constant instead of the angular momentum, which is wrong (the tests assert exactly that). It is
// right for a sphere, up to the angle error of the first-order quaternion update.
#include <type_traits>

#include "physics/kernels.hpp"

namespace rigid::physics::detail {

namespace {

// q + [0, s/2 w_W] x q, normalised.
Quat notes_rotate(const Quat& q, const Vec3& w_W, double s) {
  Quat r;
  r.coeffs() = q.coeffs() + (0.5 * s) * (Quat(0.0, w_W.x(), w_W.y(), w_W.z()) * q).coeffs();
  r.coeffs() *= 1.0 / r.norm();
  return r;
}

template <class G>
void notes_group(G g, IntegratorId which, const Model& m, Share& sh) {
  const double h = m.dt;
  constexpr bool kRotates = G::Traits::kTurns;
  for (int i = sh.all[G::kIndex].begin; i < sh.all[G::kIndex].end; ++i) {
    Motion& s = g.motion(i);
    const Linear& lin = g.linear(i);
    const LoadsRef L = g.load(i);
    const auto& rot = rot_or_none(g, i);
    const auto accel = [&](const Quat& q, const Vec3& v) {
      return Vec3(lin.accel(L.force_W(q)) - lin.gamma * v);
    };
    // I_W^-1 tau_W at orientation q and world angular velocity w_W:
    // R I^-1 R^T tau_W = R I^-1 tau_P, with the drag torque -k w.
    // Nothing produces a torque (no torque loads, no angular drag): I_W^-1 tau_W is zero, skip it.
    const bool torqued = !L.torque_free() || (L.flags & Loads::kAngularDrag) != 0;
    const auto alpha_W = [&](const Quat& q, const Vec3& w_W) {
      if constexpr (kRotates) {
        if (!torqued) return Vec3(Vec3::Zero());
        const Vec3 w_P = q.conjugate() * w_W;
        return Vec3(q * rot.omega(rot.spin_rate(L.torque_P(q) - rot.k * w_P)));
      } else {
        (void)q, (void)w_W;
        return Vec3(Vec3::Zero());
      }
    };
    const Quat q0 = s.q;
    Vec3 w0 = Vec3::Zero();  // world frame, the notes' state
    if constexpr (kRotates) {
      w0 = q0 * rot.omega(s.spin);
      sh.note_rotation(m.dt, w0);
    }
    Quat q1 = q0;
    Vec3 w1 = w0;
    switch (which) {
      case IntegratorId::kNotesExplicitEuler: {
        const Vec3 a0 = accel(q0, s.v);
        s.x += h * s.v;
        s.v += h * a0;
        if constexpr (kRotates) {
          w1 = w0 + h * alpha_W(q0, w0);
          q1 = notes_rotate(q0, w0, h);
        }
        break;
      }
      case IntegratorId::kNotesSemiImplicitEuler: {
        s.v += h * accel(q0, s.v);
        s.x += h * s.v;
        if constexpr (kRotates) {
          w1 = w0 + h * alpha_W(q0, w0);
          q1 = notes_rotate(q0, w1, h);
        }
        break;
      }
      case IntegratorId::kNotesMidpoint: {
        // Explicit midpoint: the derivative taken at the state half a step ahead.
        const Vec3 vh = s.v + 0.5 * h * accel(q0, s.v);
        Quat qh = q0;
        Vec3 wh = w0;
        if constexpr (kRotates) {
          wh = w0 + 0.5 * h * alpha_W(q0, w0);
          qh = notes_rotate(q0, w0, 0.5 * h);
        }
        s.x += h * vh;
        s.v += h * accel(qh, vh);
        if constexpr (kRotates) {
          w1 = w0 + h * alpha_W(qh, wh);
          q1 = notes_rotate(q0, wh, h);
        }
        break;
      }
      case IntegratorId::kNotesLeapfrog: {
        // v^{1/2} = v^{-1/2} + dt a^0, x^1 = x^0 + dt v^{1/2}, in kick-drift-kick form so that
        // positions and velocities are reported at the same instants. The closing half kick
        // takes the linear drags at the new velocity, v1 = (v½ + h/2 a_ext) / (1 + h/2 gamma):
        // still explicit arithmetic, and it keeps the scheme second order (drag taken at v½
        // would make it first order); without drag it is the notes' leapfrog exactly.
        const Vec3 vh = s.v + 0.5 * h * accel(q0, s.v);
        Vec3 wh = w0;
        if constexpr (kRotates) {
          wh = w0 + 0.5 * h * alpha_W(q0, w0);
          q1 = notes_rotate(q0, wh, h);
        }
        s.x += h * vh;
        s.v = (vh + 0.5 * h * lin.accel(L.force_W(q1))) / (1.0 + 0.5 * h * lin.gamma);
        if constexpr (kRotates) {
          const Vec3 w_P = q1.conjugate() * wh + 0.5 * h * rot.omega(rot.spin_rate(L.torque_P(q1)));
          w1 = q1 * w_P.cwiseQuotient(Vec3::Ones() + 0.5 * h * rot.drag_rates());
        }
        break;
      }
      default:
        break;
    }
    if constexpr (kRotates) {
      s.q = q1;
      s.spin = rot.spin_of(q1.conjugate() * w1);
    }
  }
}

}  // namespace

void step_notes(const Model& m, Data& d, IntegratorId which, Share& sh) {
  notes_group(group(m, d, kTranslationGroup), which, m, sh);
  notes_group(group(m, d, kSteadySpinGroup), which, m, sh);
  notes_group(group(m, d, kPrecessionGroup), which, m, sh);
  notes_group(group(m, d, kTumblingGroup), which, m, sh);
}

}  // namespace rigid::physics::detail
