// Kick-drift-kick with the free-rotor splitting of Dullweber, Leimkuhler & McLachlan, "Symplectic
// splitting methods for rigid body molecular dynamics", J. Chem. Phys. 107 (1997):
//   kick  h/2:  v += h/2 a(q), m += h/2 tau_P(q)          (drags as exact decays)
//   drift h:    x += h v;  free rotor split into the exact rotations about each principal axis,
//               R1(h/2) R2(h/2) R3(h) R2(h/2) R1(h/2), where Ri(t) turns the body about P's axis i
//               by t m_i / I_i and turns m the other way (m' = m x w_i e_i);
//   kick  h/2.
// Symplectic, time-reversible and second order; each sub-rotation is exact, the splitting is not.
#include <type_traits>

#include "physics/kernels.hpp"

namespace rigid::physics::detail {

namespace {

// Exact flow of the sub-Hamiltonian m_i^2 / (2 I_i) for time t.
inline void axis_rotation(int i, double t, const Vec3& inv_I, Vec3& m, Quat& q) {
  const double theta = t * m[i] * inv_I[i];
  double ch, sinc;
  cos_sinc(0.5 * theta, ch, sinc);
  const double sh = 0.5 * theta * sinc;
  const double c = ch * ch - sh * sh, s = 2.0 * ch * sh;
  const int j = (i + 1) % 3, k = (i + 2) % 3;
  const double mj = m[j], mk = m[k];
  m[j] = c * mj + s * mk;
  m[k] = -s * mj + c * mk;
  Quat e(ch, 0.0, 0.0, 0.0);
  e.vec()[i] = sh;
  q = q * e;
}

template <class G>
void dlm_group(G g, const Model& m, Share& sh) {
  constexpr bool kRotates = G::Traits::kTurns;
  const double h = m.dt;
  for (int i = sh.all[G::kIndex].begin; i < sh.all[G::kIndex].end; ++i) {
    Motion& s = g.motion(i);
    const Linear& lin = g.linear(i);
    const LoadsRef L = g.load(i);
    const auto& rot = rot_or_none(g, i);
    const TransCoef& half = m.tc(lin, kHalf);
    Vec3 rate = Vec3::Zero();
    if constexpr (kRotates) {
      rate = rot.drag_rates();
      sh.note_rotation(m.dt, rot.omega(s.spin));
    }
    const auto kick_all = [&] {
      kick(half, lin.accel(L.force_W(s.q)), s.v);
      if constexpr (kRotates) {
        kick_angular(rot.spin_rate(L.torque_P(s.q)), rate, 0.5 * h, s.spin);
      }
    };
    kick_all();
    s.x += h * s.v;
    if constexpr (kRotates) {
      if constexpr (std::is_same_v<std::decay_t<decltype(rot)>, DiagRot>) {
        axis_rotation(0, 0.5 * h, rot.inv_I, s.spin, s.q);
        axis_rotation(1, 0.5 * h, rot.inv_I, s.spin, s.q);
        axis_rotation(2, h, rot.inv_I, s.spin, s.q);
        axis_rotation(1, 0.5 * h, rot.inv_I, s.spin, s.q);
        axis_rotation(0, 0.5 * h, rot.inv_I, s.spin, s.q);
      } else {
        s.q = s.q * quat_exp(h * s.spin);  // isotropic: the free rotor is exactly this
      }
      renormalize(s.q);
    }
    kick_all();
  }
}

}  // namespace

void step_dlm(const Model& m, Data& d, Share& sh) {
  dlm_group(group(m, d, kTranslationGroup), m, sh);
  dlm_group(group(m, d, kSteadySpinGroup), m, sh);
  dlm_group(group(m, d, kPrecessionGroup), m, sh);
  dlm_group(group(m, d, kTumblingGroup), m, sh);
}

}  // namespace rigid::physics::detail
