// hybrid4's loaded bodies over lanes of RIGID_LANE_WIDTH bodies (see hybrid_lanes.hpp for why the
// result is the same in every build). Compiled once per width by server/physics/CMakeLists.txt,
// which sets RIGID_LANE_WIDTH, RIGID_LANE_NS and the instruction set.
//
// One body's step is integrate_exact.cpp's compose_loaded<TripleJump> with fast_drift, the
// composition of S(s) = kick(s/2) . drift(s) . kick(s/2) over the stages (g1, g0, g1) h (Yoshida,
// Phys. Lett. A 150, 1990), merged half kicks, the translation by the exact drag flow with the
// acceleration interpolated linearly over each stage (translation.hpp), and the drift
//   general:      X1(s/2) A(s) X1(s/2), A the axisymmetric rotor of moments (I2, I2, I3), X1 the
//                 turn about axis 1 of the remainder (a1 - a2) m1^2 / 2 (Touma & Wisdom 1994);
//   axisymmetric: A(s) itself (Landau & Lifshitz section 33).
// The scalar code stays the reference for what each line computes; this file restates it per lane.
#include "physics/hybrid_lanes.hpp"
#include "physics/lanes.hpp"

namespace rigid::physics::detail::RIGID_LANE_NS {

namespace {

static_assert(W <= LaneBatch::kMax);

// integrate_exact.cpp's axis_turn about P's x axis: the exact flow of d m1^2 / 2 over t.
inline void axis_turn_x(V d, double t, V3& m, Q& q) {
  const V theta = t * d * m.x;
  V ch, sinc;
  cos_sinc(0.5 * theta, ch, sinc);
  const V sh = 0.5 * theta * sinc;
  const V c = ch * ch - sh * sh, sn = 2.0 * ch * sh;
  const V my = m.y, mz = m.z;
  m.y = c * my + sn * mz;
  m.z = -sn * my + c * mz;
  q = {q.w * ch - q.x * sh, q.w * sh + q.x * ch, q.y * ch + q.z * sh, q.z * ch - q.y * sh};
}

// integrate_exact.cpp's axisym_turn: the axisymmetric free rotor (moments 1/a, 1/a, 1/c) over s.
inline void axisym_turn(V a, V c, double s, V3& m, Q& q) {
  const V hs = 0.5 * s * a;
  V cw, sw;
  cos_sinc_sq(hs * hs * (m.x * m.x + m.y * m.y + m.z * m.z), cw, sw);
  sw *= hs;
  const V phi = s * (c - a) * m.z;
  V cz, sz;
  cos_sinc_sq(0.25 * phi * phi, cz, sz);
  sz *= 0.5 * phi;
  const V c2 = cz * cz - sz * sz, s2 = 2.0 * cz * sz;
  const Q dq{cw * cz - sw * m.z * sz, sw * (m.x * cz + m.y * sz), sw * (m.y * cz - m.x * sz),
             cw * sz + sw * m.z * cz};
  q = mul(q, dq);
  const V m1 = m.x, m2 = m.y;
  m.x = c2 * m1 + s2 * m2;
  m.y = -s2 * m1 + c2 * m2;
}

// The lanes of a LaneBatch while they step.
struct Lanes {
  Q q;
  V3 x, v, m;
  V3 g, inv_m, inv_I, decay;
  bool drag = false;  // some lane has angular drag: kicks take the decay per lane
  V E[2], p1[2], p2[2], q2[2], q3[2];
  Mask body_force, world_torque, lever;
  bool any_body_force = false, any_world_torque = false, any_lever = false;
  V3 f_W, f_P, tau_P, tau_W;
  V fr[3][3];

  explicit Lanes(const LaneBatch& b)
      : q{load(b.qw), load(b.qx), load(b.qy), load(b.qz)},
        x(load3(b.x)),
        v(load3(b.v)),
        m(load3(b.m)),
        g(load3(b.g)),
        inv_m(load3(b.inv_m)),
        inv_I(load3(b.inv_I)),
        decay(load3(b.decay)),
        body_force(load_mask(b.body_force)),
        world_torque(load_mask(b.world_torque)),
        lever(load_mask(b.lever)),
        f_W(load3(b.f_W)),
        f_P(load3(b.f_P)),
        tau_P(load3(b.tau_P)),
        tau_W(load3(b.tau_W)) {
    for (int k = 0; k < 2; ++k) {
      E[k] = load(b.E[k]);
      p1[k] = load(b.p1[k]);
      p2[k] = load(b.p2[k]);
      q2[k] = load(b.q2[k]);
      q3[k] = load(b.q3[k]);
    }
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
        fr[r][c] = load(b.fr[r][c]);
    drag = any((decay.x != 0.0) | (decay.y != 0.0) | (decay.z != 0.0));
    any_body_force = any(body_force);
    any_world_torque = any(world_torque);
    any_lever = any(lever);
  }
  void write(LaneBatch& b) const {
    store(b.qw, q.w);
    store(b.qx, q.x);
    store(b.qy, q.y);
    store(b.qz, q.z);
    store3(b.x, x);
    store3(b.v, v);
    store3(b.m, m);
  }

  // Loads::force_W, then Linear::accel: g + (1/m) f_W.
  V3 accel(const Q& qq) const {
    V3 f = f_W;
    if (any_body_force) f = select(body_force, f_W + rotate(qq, f_P), f_W);
    return {g.x + inv_m.x * f.x, g.y + inv_m.y * f.y, g.z + inv_m.z * f.z};
  }
  // Loads::torque_P: tau_P + q* tau_W + the lever term vee(skew part of R(q*) fr).
  V3 torque(const Q& qq) const {
    V3 t = tau_P;
    if (any_world_torque) t = select(world_torque, t + rotate(conj(qq), tau_W), t);
    if (any_lever) {
      // R = R(q*) (Eigen's toRotationMatrix); n = R fr, of which only the antisymmetric part
      // counts.
      const Q c = conj(qq);
      const V tx = 2.0 * c.x, ty = 2.0 * c.y, tz = 2.0 * c.z;
      const V twx = tx * c.w, twy = ty * c.w, twz = tz * c.w;
      const V txx = tx * c.x, txy = ty * c.x, txz = tz * c.x;
      const V tyy = ty * c.y, tyz = tz * c.y, tzz = tz * c.z;
      const V R[3][3] = {{1.0 - (tyy + tzz), txy - twz, txz + twy},
                         {txy + twz, 1.0 - (txx + tzz), tyz - twx},
                         {txz - twy, tyz + twx, 1.0 - (txx + tyy)}};
      const auto n = [&](int i, int j) {
        return R[i][0] * fr[0][j] + R[i][1] * fr[1][j] + R[i][2] * fr[2][j];
      };
      const V3 lev{n(2, 1) - n(1, 2), n(0, 2) - n(2, 0), n(1, 0) - n(0, 1)};
      t = select(lever, t + lev, t);
    }
    return t;
  }
  // kernels.hpp's kick_angular: spin_i <- e^{-d_i s} spin_i + s phi1(-d_i s) rate_i, with no drag
  // spin += s rate.
  void kick(const V3& rate, double s) {
    if (!drag) {
      m = {m.x + s * rate.x, m.y + s * rate.y, m.z + s * rate.z};
      return;
    }
    V* spin[3] = {&m.x, &m.y, &m.z};
    const V* r[3] = {&rate.x, &rate.y, &rate.z};
    const V* d[3] = {&decay.x, &decay.y, &decay.z};
    for (int i = 0; i < 3; ++i) {
      for (int l = 0; l < W; ++l) {
        const double di = (*d[i])[l];
        if (di == 0.0) {
          (*spin[i])[l] += s * (*r[i])[l];
        } else {
          const double z = -di * s;
          const double em1 = std::expm1(z);
          (*spin[i])[l] = (1.0 + em1) * (*spin[i])[l] + s * (em1 / z) * (*r[i])[l];
        }
      }
    }
  }
  // translation.hpp's translate over a stage with coefficient set k.
  void translate(int k, const V3& a0, const V3& a1) {
    const V3 da = a1 - a0;
    x = {x.x + (p1[k] * v.x + q2[k] * a0.x + q3[k] * da.x),
         x.y + (p1[k] * v.y + q2[k] * a0.y + q3[k] * da.y),
         x.z + (p1[k] * v.z + q2[k] * a0.z + q3[k] * da.z)};
    v = {E[k] * v.x + p1[k] * a0.x + p2[k] * da.x, E[k] * v.y + p1[k] * a0.y + p2[k] * da.y,
         E[k] * v.z + p1[k] * a0.z + p2[k] * da.z};
  }
  // integrate_exact.cpp's split_drift (general) or fast_drift (axisymmetric).
  void drift(bool general, double s) {
    if (general) {
      const V d1 = inv_I.x - inv_I.y;
      axis_turn_x(d1, 0.5 * s, m, q);
      axisym_turn(inv_I.y, inv_I.z, s, m, q);
      axis_turn_x(d1, 0.5 * s, m, q);
    } else {
      axisym_turn(inv_I.x, inv_I.z, s, m, q);
    }
    renormalize(q);
  }
};

}  // namespace

// compose_loaded<TripleJump> (integrate_exact.cpp), the stages' half kicks merged.
void step(LaneBatch& b, const LaneStages& st) {
  Lanes L(b);
  V3 a0 = L.accel(L.q);
  V3 rate = L.torque(L.q);
  L.kick(rate, 0.5 * st.s[0]);
  for (int k = 0; k < LaneStages::kStages; ++k) {
    L.drift(st.general, st.s[k]);
    const V3 a1 = L.accel(L.q);
    rate = L.torque(L.q);
    L.translate(st.size[k], a0, a1);
    const double next = k + 1 < LaneStages::kStages ? st.s[k + 1] : 0.0;
    L.kick(rate, 0.5 * (st.s[k] + next));
    a0 = a1;
  }
  L.write(b);
}

}  // namespace rigid::physics::detail::RIGID_LANE_NS
