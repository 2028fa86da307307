// Classical fourth-order Runge-Kutta on the full state (x, v, q, w_P):
//   x' = v,  v' = a(q) - gamma v,  q' = q x [0, w_P] / 2,  w_P' = I^-1 (tau_P(q) - k w_P - w_P x I
//   w_P).
// Loads are re-evaluated at each stage with that stage's orientation, so body-frame forces and
// lever arms turn with the body inside the step (holding them fixed over the stages, as MuJoCo does
// with xfrc_applied, costs the method its order). q is normalised once, at the end of the step.
#include <type_traits>

#include "physics/kernels.hpp"

namespace rigid::physics::detail {

namespace {

struct Deriv {
  Vec3 dx, dv, ds;
  Eigen::Vector4d dq;  // Eigen coefficient order (x, y, z, w)
};

template <class Rot>
constexpr bool kGyroscopic = std::is_same_v<Rot, DiagRot>;

template <class G>
void rk4_group(G g, const Model& m, Share& sh) {
  const double h = m.dt;
  constexpr bool kRotates = G::Traits::kTurns;
  for (int i = sh.all[G::kIndex].begin; i < sh.all[G::kIndex].end; ++i) {
    Motion& s = g.motion(i);
    const Linear& lin = g.linear(i);
    const LoadsRef L = g.load(i);
    const auto& rot = rot_or_none(g, i);
    // The stages' q drift off the unit sphere; loads that turn with the body are evaluated at the
    // normalised q (one reciprocal, not four divisions), the others need no q at all.
    const bool turns =
        !L.orientation_free_force() || (L.flags & (Loads::kWorldTorque | Loads::kLever));
    const auto f = [&](const Motion& y) {
      Deriv d;
      Quat qn = y.q;
      if (kRotates && turns) qn.coeffs() *= 1.0 / y.q.norm();
      d.dx = y.v;
      d.dv = lin.accel(L.force_W(qn)) - lin.gamma * y.v;
      if constexpr (kRotates) {
        const Vec3 w = rot.omega(y.spin);
        Vec3 tau = L.torque_P(qn) - rot.k * w;
        if constexpr (kGyroscopic<std::decay_t<decltype(rot)>>) tau -= w.cross(y.spin);
        d.ds = rot.spin_rate(tau);
        d.dq = 0.5 * (y.q * Quat(0.0, w.x(), w.y(), w.z())).coeffs();
      } else {
        d.ds.setZero();
        d.dq.setZero();
      }
      return d;
    };
    const auto add = [&](const Deriv& d, double c) {
      Motion y;
      y.x = s.x + c * d.dx;
      y.v = s.v + c * d.dv;
      y.spin = s.spin + c * d.ds;
      y.q.coeffs() = s.q.coeffs() + c * d.dq;
      return y;
    };
    if constexpr (kRotates) sh.note_rotation(m.dt, rot.omega(s.spin));
    const Deriv k1 = f(s);
    const Deriv k2 = f(add(k1, 0.5 * h));
    const Deriv k3 = f(add(k2, 0.5 * h));
    const Deriv k4 = f(add(k3, h));
    const double c = h / 6.0;
    s.x += c * (k1.dx + 2.0 * k2.dx + 2.0 * k3.dx + k4.dx);
    s.v += c * (k1.dv + 2.0 * k2.dv + 2.0 * k3.dv + k4.dv);
    if constexpr (kRotates) {
      s.spin += c * (k1.ds + 2.0 * k2.ds + 2.0 * k3.ds + k4.ds);
      s.q.coeffs() += c * (k1.dq + 2.0 * k2.dq + 2.0 * k3.dq + k4.dq);
      renormalize(s.q);
    }
  }
}

}  // namespace

void step_rk4(const Model& m, Data& d, Share& sh) {
  rk4_group(group(m, d, kTranslationGroup), m, sh);
  rk4_group(group(m, d, kSteadySpinGroup), m, sh);
  rk4_group(group(m, d, kPrecessionGroup), m, sh);
  rk4_group(group(m, d, kTumblingGroup), m, sh);
}

}  // namespace rigid::physics::detail
