// The implicit gyroscopic step (E. Catto, "Numerical Methods", GDC 2015; Box2D v3 and Bullet's
// BT_ENABLE_GYROSCOPIC_FORCE_IMPLICIT_BODY do the same):
//   1. explicit torque:  w_a = w + h I^-1 tau_P   (angular drag as an exact decay);
//   2. gyroscopic term, implicit backward Euler in the body frame, one Newton step from w_a:
//        f(w) = I (w - w_a) + h w x I w = 0,  J = I + h ([w_a]x I - [I w_a]x),
//        w = w_a - J^-1 f(w_a) = w_a - J^-1 (h w_a x I w_a);
//   3. orientation: q <- q exp(h w), the exact rotation at constant body-frame w.
// Translation is semi-implicit Euler with linear drag as an exact decay. First order; stable at
// any spin, but it drains rotational energy (the backward-Euler damping of the gyroscopic flow).
#include <type_traits>

#include "physics/kernels.hpp"

namespace rigid::physics::detail {

namespace {

template <class G>
void implicit_gyro_group(G g, const Model& m, Share& sh) {
  constexpr bool kRotates = G::Traits::kTurns;
  const double h = m.dt;
  for (int i = sh.all[G::kIndex].begin; i < sh.all[G::kIndex].end; ++i) {
    Motion& s = g.motion(i);
    const Linear& lin = g.linear(i);
    const LoadsRef L = g.load(i);
    const TransCoef& k = m.tc(lin, kFull);
    kick(k, lin.accel(L.force_W(s.q)), s.v);
    s.x += h * s.v;
    if constexpr (kRotates) {
      const auto& rot = g.rot(i);
      using Rot = std::decay_t<decltype(rot)>;
      sh.note_rotation(m.dt, rot.omega(s.spin));
      kick_angular(rot.spin_rate(L.torque_P(s.q)), rot.drag_rates(), h, s.spin);
      Vec3 w = rot.omega(s.spin);
      if constexpr (std::is_same_v<Rot, DiagRot>) {
        const Vec3 Iw = rot.I.cwiseProduct(w);
        const Mat3 J = Mat3(rot.I.asDiagonal()) + h * (skew(w) * rot.I.asDiagonal() - skew(Iw));
        w -= J.inverse() * (h * w.cross(Iw));  // fixed-size 3x3: Eigen's cofactor inverse
        s.spin = rot.spin_of(w);
      }
      s.q = s.q * quat_exp(h * w);
      renormalize(s.q);
    }
  }
}

}  // namespace

void step_implicit_gyro(const Model& m, Data& d, Share& sh) {
  implicit_gyro_group(group(m, d, kTranslationGroup), m, sh);
  implicit_gyro_group(group(m, d, kSteadySpinGroup), m, sh);
  implicit_gyro_group(group(m, d, kPrecessionGroup), m, sh);
  implicit_gyro_group(group(m, d, kTumblingGroup), m, sh);
}

}  // namespace rigid::physics::detail
