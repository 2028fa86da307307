// The exact free rotor's cached step over lanes of RIGID_LANE_WIDTH general bodies (see
// rotor_lanes.hpp). Every line restates free_rotor.cpp's advance_rotor (RotorUpdate::kPinned:
// case_coords, phase_of, the addition theorem, finish_step) and
// integrate_exact.cpp's drift_cached (q <- q dq, renormalize) with the same operations in the same
// order; the parenthesised groupings below are the ones C++ and Eigen evaluate there. Change one
// side and the other with it: lanes_test's Lanes.FreeBodiesStepBitForBitAsTheScalarCode compares
// them bit for bit (RIGID_LANES=1 runs the scalar code).
#include "physics/gauss_legendre.hpp"
#include "physics/lanes.hpp"
#include "physics/rotor_lanes.hpp"

namespace rigid::physics::detail::RIGID_LANE_NS {

namespace {

static_assert(RotorPlanLanes::kMax % W == 0);

// Eigen's quaternion product a b as its SSE2 path computes it (Geometry_SIMD.h, quat_product for
// double): the terms paired as there.
inline Q mul_eigen(const Q& a, const Q& b) {
  return {(a.w * b.w - a.y * b.y) - (a.z * b.z + a.x * b.x),
          (a.w * b.x + a.y * b.z) - (a.z * b.y - a.x * b.w),
          (a.w * b.y + a.y * b.w) + (a.z * b.x - a.x * b.z),
          (a.w * b.z - a.y * b.x) + (a.z * b.w + a.x * b.y)};
}

// math.hpp's renormalize with Eigen's sum of squares over the coefficients (x, y, z, w) in two
// packets: (x^2 + z^2) + (y^2 + w^2).
inline void renormalize_eigen(Q& q) {
  const V n2 = (q.x * q.x + q.z * q.z) + (q.y * q.y + q.w * q.w);
  const Mask near = abs(n2 - 1.0) < 1e-8;
  const V f = 1.5 - 0.5 * n2;
  Q out{q.w * f, q.x * f, q.y * f, q.z * f};
  if (!all(near)) {
    for (int l = 0; l < W; ++l) {
      if (!near[l]) {
        const double n = std::sqrt(n2[l]);
        out.w[l] = q.w[l] / n;
        out.x[l] = q.x[l] / n;
        out.y[l] = q.y[l] / n;
        out.z[l] = q.z[l] / n;
      }
    }
  }
  q = out;
}

// sqrt(x) per lane, as the scalar code writes it (IEEE sqrt: exact per lane).
inline V sqrt(V x) {
  V r;
  for (int l = 0; l < W; ++l)
    r[l] = std::sqrt(x[l]);
  return r;
}

}  // namespace

void rotor_step(RotorStateLanes& st, const RotorPlanLanes& p, const unsigned char* flags, int off) {
  // The lanes' flags bytes widened to 64 bits in one go (vpmovzxbq), not a lane at a time.
  using Bytes = unsigned char __attribute__((vector_size(W)));
  Bytes fb;
  std::memcpy(&fb, flags + off, sizeof fb);
  const Mask fl = __builtin_convertvector(fb, Mask);
  const Mask case_b = (fl & kRotorFlagCaseB) != 0;
  const Mask nodes = fl & kRotorFlagNodes;
  const V s = select((fl & kRotorFlagNegative) != 0, splat(-1.0), splat(1.0));
  const V ia = load(p.ia + off), ib = load(p.ib + off);
  const V k2 = load(p.k2 + off), mc = load(p.mc + off);
  const V C = load(p.C + off), D = load(p.D + off), S = load(p.S + off);
  const V a = load(p.a + off), bb = load(p.b + off), c = load(p.c + off), lin = load(p.lin + off);
  // As plan_core makes them from 1/G: cG = c / G, abG2 = a b / G^2.
  const V iG = load(p.iG + off);
  const V cG = c * iG, abG2 = a * bb * iG * iG;
  // As plan_core makes them: cn_bias = (a > 0 ? 0 : 1), mS2 = m sn sn, mSC = m sn C.
  const V cn_bias = select(a > 0.0, splat(0.0), splat(1.0));
  const V mS2 = k2 * S * S, mSC = k2 * S * C;
  const V G = load(p.G + off);
  const V3 m = V3{load(st.m[0] + off), load(st.m[1] + off), load(st.m[2] + off)};

  // case_coords
  const V x1 = select(case_b, m.z, m.x), x2 = select(case_b, -m.y, m.y);
  // (x3 is read only by RotorUpdate::kIncrement: kPinned rebuilds m from the phase.)
  // phase_of, a plan not fresh: one Newton step onto sn^2 + cn^2 = 1.
  V s0 = x2 * ib;
  V c0 = s * x1 * ia + cn_bias;
  const V n2 = s0 * s0 + c0 * c0;
  const Mask near = abs(n2 - 1.0) < 1e-8;
  V f = 1.5 - 0.5 * n2;
  if (!all(near)) {
    for (int l = 0; l < W; ++l) {
      if (!near[l]) f[l] = 1.0 / std::sqrt(n2[l]);
    }
  }
  s0 *= f;
  c0 *= f;
  V d0;
  {
    const V r = mc + k2 * c0 * c0;
    for (int l = 0; l < W; ++l)
      d0[l] = std::sqrt(r[l]);
  }
  // The psi integral's nodes by the addition theorem, summed as one fraction. Node i's weight
  // X w_i / 2 with w_i that of the lane's rule (2, 3 or 4 nodes), as make_rotor_plan makes it.
  V top = splat(0.0), bottom = splat(1.0);
  const V sc0 = s0 * c0, ss0 = s0 * s0;
  const V half_X = 0.5 * load(p.X + off);
  const Mask two = nodes == 2, three = nodes == 3;
  for (int i = 0; i < RotorPlanLanes::kNodes; ++i) {
    const Mask on = nodes > i;
    if (!any(on)) break;
    const V rule_w =
        select(two, splat(kGL2.w[i]), select(three, splat(kGL3.w[i]), splat(kGL4.w[i])));
    const V num = d0 * load(p.Dn[i] + off) - load(p.mSCn[i] + off) * sc0;
    const V den = (1.0 - load(p.mS2n[i] + off) * ss0) + cG * num;
    top = select(on, top * den + (half_X * rule_w) * num * bottom, top);
    bottom = select(on, bottom * den, bottom);
  }
  const V integral = top / bottom;
  const V e = mS2 * ss0;
  const V inv = 1.0 / (1.0 - e);
  const V sn1 = (s0 * C * D + S * c0 * d0) * inv;
  const V cn1 = (c0 * C - s0 * d0 * S * D) * inv;
  const V dn1 = (d0 * D - mSC * sc0) * inv;
  const V y1 = s * a * cn1, y2 = bb * sn1, y3 = s * c * dn1;
  const V correction = abG2 * integral;

  // finish_step: both frames unnormalised, d scaled once.
  const V dpsi = s * (lin - correction);
  V cz, sincz;
  cos_sinc(0.5 * dpsi, cz, sincz);
  const V sz = 0.5 * dpsi * sincz;
  const V w0 = G + c * d0;
  const V w1 = G + s * y3;
  const Q p0{w0, s * bb * s0, -a * c0, splat(0.0)};
  const Q p1{w1, s * y2, -s * y1, splat(0.0)};
  const Q u{cz * p1.w, cz * p1.x - sz * p1.y, cz * p1.y + sz * p1.x, sz * p1.w};
  Q d = mul_eigen(conj(p0), u);
  const V scale = 1.0 / (2.0 * G * sqrt(w0 * w1));
  d = {d.w * scale, d.x * scale, d.y * scale, d.z * scale};
  // Back from case coordinates.
  const V3 m1{select(case_b, y3, y1), select(case_b, -y2, y2), select(case_b, y1, y3)};
  const Q dq{d.w, select(case_b, d.z, d.x), select(case_b, -d.y, d.y), select(case_b, d.x, d.z)};
  store(st.m[0] + off, m1.x);
  store(st.m[1] + off, m1.y);
  store(st.m[2] + off, m1.z);

  // drift_cached: q <- q dq, renormalised.
  Q q{load(st.qw + off), load(st.qx + off), load(st.qy + off), load(st.qz + off)};
  q = mul_eigen(q, dq);
  renormalize_eigen(q);
  store(st.qw + off, q.w);
  store(st.qx + off, q.x);
  store(st.qy + off, q.y);
  store(st.qz + off, q.z);
}

}  // namespace rigid::physics::detail::RIGID_LANE_NS
