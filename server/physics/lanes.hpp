// What the per-instruction-set kernels share (hybrid_lanes_kernel.cpp, rotor_lanes_kernel.cpp):
// lanes of W doubles (GCC / Clang vector extensions: arithmetic on V is lane-wise IEEE double
// arithmetic), masks, small vectors and quaternions over lanes, and math.hpp's series restated per
// lane. Included only by those kernels, each compiled once per width with RIGID_LANE_WIDTH and
// RIGID_LANE_NS set (server/physics/CMakeLists.txt): everything here lives in that namespace, so
// no copy compiled for one instruction set can stand in for another's.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>

#if defined(__x86_64__)
#include <immintrin.h>
#endif

#ifndef RIGID_LANE_WIDTH
#error "RIGID_LANE_WIDTH must be set by the build"
#endif

namespace rigid::physics::detail::RIGID_LANE_NS {

constexpr int W = RIGID_LANE_WIDTH;
// math.hpp's kSmallAngle (hybrid_lanes.cpp checks that they agree).
constexpr double kSmallAngle = 1.0 / 16.0;
// GCC / Clang vector extensions: arithmetic on V is lane-wise IEEE double arithmetic.
using V = double __attribute__((vector_size(W * sizeof(double))));
using Mask = std::int64_t __attribute__((vector_size(W * sizeof(double))));  // lanes: -1 or 0

inline V splat(double x) {
  V v;
  for (int l = 0; l < W; ++l)
    v[l] = x;
  return v;
}
inline V select(Mask m, V a, V b) {
  return reinterpret_cast<V>((reinterpret_cast<Mask>(a) & m) | (reinterpret_cast<Mask>(b) & ~m));
}
// Whether some lane / every lane of a mask is set. The branches they choose skip work whose
// lanes select() would discard, so only speed depends on them. One test instruction for the
// lanes of each instruction set: g++ makes of a plain reduction loop a move of every lane to a
// general register (bench/notes/step-kernels.md, "SIMD lanes").
inline bool any(Mask m) {
#if RIGID_LANE_WIDTH == 8 && defined(__AVX512F__)
  const __m512i v = reinterpret_cast<__m512i>(m);
  return _mm512_test_epi64_mask(v, v) != 0;
#elif RIGID_LANE_WIDTH == 4 && defined(__AVX__)
  return _mm256_movemask_pd(reinterpret_cast<__m256d>(m)) != 0;  // lanes are -1 or 0
#elif RIGID_LANE_WIDTH == 2 && defined(__SSE2__)
  return _mm_movemask_pd(reinterpret_cast<__m128d>(m)) != 0;
#else
  std::int64_t r = 0;
  for (int l = 0; l < W; ++l)
    r |= m[l];
  return r != 0;
#endif
}
inline bool all(Mask m) {
#if RIGID_LANE_WIDTH == 8 && defined(__AVX512F__)
  const __m512i v = reinterpret_cast<__m512i>(m);
  return _mm512_test_epi64_mask(v, v) == 0xFF;
#elif RIGID_LANE_WIDTH == 4 && defined(__AVX__)
  return _mm256_movemask_pd(reinterpret_cast<__m256d>(m)) == 0xF;
#elif RIGID_LANE_WIDTH == 2 && defined(__SSE2__)
  return _mm_movemask_pd(reinterpret_cast<__m128d>(m)) == 0x3;
#else
  std::int64_t r = -1;
  for (int l = 0; l < W; ++l)
    r &= m[l];
  return r != 0;
#endif
}
inline V abs(V x) {
  return select(x < 0.0, -x, x);
}

struct V3 {
  V x, y, z;
};
struct Q {
  V w, x, y, z;
};

inline V3 operator+(const V3& a, const V3& b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
inline V3 operator-(const V3& a, const V3& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
inline V3 select(Mask m, const V3& a, const V3& b) {
  return {select(m, a.x, b.x), select(m, a.y, b.y), select(m, a.z, b.z)};
}
inline V3 cross(const V3& a, const V3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
// q v q* for a unit q: v + w t + u x t with t = 2 u x v (the form Eigen's Quaternion uses).
inline V3 rotate(const Q& q, const V3& v) {
  const V3 u{q.x, q.y, q.z};
  V3 t = cross(u, v);
  t = {t.x + t.x, t.y + t.y, t.z + t.z};
  const V3 ut = cross(u, t);
  return {v.x + q.w * t.x + ut.x, v.y + q.w * t.y + ut.y, v.z + q.w * t.z + ut.z};
}
inline Q conj(const Q& q) {
  return {q.w, -q.x, -q.y, -q.z};
}
// Hamilton product a b.
inline Q mul(const Q& a, const Q& b) {
  return {
      a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z, a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
      a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x, a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}

// math.hpp's cos_sinc per lane: each lane takes the series its |t| calls for, libm beyond.
inline void cos_sinc(V t, V& c, V& sinc) {
  const V t2 = t * t;
  const V at = abs(t);
  const Mask m1 = at < 1e-3, m2 = at < 2e-2, m3 = at < kSmallAngle;
  c = splat(1.0);
  sinc = splat(1.0);
  if (any(m1)) {
    const V c1 = 1.0 + t2 * (-1.0 / 2 + t2 * (1.0 / 24));
    const V s1 = 1.0 + t2 * (-1.0 / 6 + t2 * (1.0 / 120));
    c = select(m1, c1, c);
    sinc = select(m1, s1, sinc);
  }
  if (const Mask m = m2 & ~m1; any(m)) {
    const V c2 = 1.0 + t2 * (-1.0 / 2 + t2 * (1.0 / 24 + t2 * (-1.0 / 720 + t2 * (1.0 / 40320))));
    const V s2 =
        1.0 + t2 * (-1.0 / 6 + t2 * (1.0 / 120 + t2 * (-1.0 / 5040 + t2 * (1.0 / 362880))));
    c = select(m, c2, c);
    sinc = select(m, s2, sinc);
  }
  if (const Mask m = m3 & ~m2; any(m)) {
    const V c3 =
        1.0 + t2 * (-1.0 / 2 +
                    t2 * (1.0 / 24 +
                          t2 * (-1.0 / 720 + t2 * (1.0 / 40320 + t2 * (-1.0 / 3628800 +
                                                                       t2 * (1.0 / 479001600))))));
    const V s3 =
        1.0 +
        t2 * (-1.0 / 6 +
              t2 * (1.0 / 120 +
                    t2 * (-1.0 / 5040 + t2 * (1.0 / 362880 + t2 * (-1.0 / 39916800 +
                                                                   t2 * (1.0 / 6227020800.0))))));
    c = select(m, c3, c);
    sinc = select(m, s3, sinc);
  }
  if (!all(m3)) {
    for (int l = 0; l < W; ++l) {
      if (!m3[l]) {
        c[l] = std::cos(t[l]);
        sinc[l] = std::sin(t[l]) / t[l];
      }
    }
  }
}

// math.hpp's cos_sinc_sq per lane.
inline void cos_sinc_sq(V t2, V& c, V& sinc) {
  const Mask m = t2 < kSmallAngle * kSmallAngle;
  c = 1.0 + t2 * (-1.0 / 2 +
                  t2 * (1.0 / 24 +
                        t2 * (-1.0 / 720 + t2 * (1.0 / 40320 +
                                                 t2 * (-1.0 / 3628800 + t2 * (1.0 / 479001600))))));
  sinc =
      1.0 +
      t2 * (-1.0 / 6 +
            t2 * (1.0 / 120 +
                  t2 * (-1.0 / 5040 +
                        t2 * (1.0 / 362880 + t2 * (-1.0 / 39916800 + t2 * (1.0 / 6227020800.0))))));
  if (!all(m)) {
    for (int l = 0; l < W; ++l) {
      if (!m[l]) {
        const double t = std::sqrt(t2[l]);
        c[l] = std::cos(t);
        sinc[l] = std::sin(t) / t;
      }
    }
  }
}

// math.hpp's renormalize (its arithmetic, in this file's order: hybrid4's loaded bodies): one
// Newton step on |q|^2 = 1, a full normalisation when |q| is far off.
inline void renormalize(Q& q) {
  const V n2 = q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z;
  const Mask near = abs(n2 - 1.0) < 1e-8;
  const V f = 1.5 - 0.5 * n2;
  const Q newton{q.w * f, q.x * f, q.y * f, q.z * f};
  if (!all(near)) {
    for (int l = 0; l < W; ++l) {
      if (!near[l]) {
        const double n = std::sqrt(n2[l]);
        q.w[l] /= n;
        q.x[l] /= n;
        q.y[l] /= n;
        q.z[l] /= n;
      }
    }
  }
  q = {select(near, newton.w, q.w), select(near, newton.x, q.x), select(near, newton.y, q.y),
       select(near, newton.z, q.z)};
}

inline V load(const double* p) {
  V v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
inline void store(double* p, V v) {
  std::memcpy(p, &v, sizeof v);
}
inline Mask load_mask(const std::int64_t* p) {
  Mask v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
// Rows of 8 doubles (the batches' component-major arrays) to and from lanes.
inline V3 load3(const double (*a)[8]) {
  return {load(a[0]), load(a[1]), load(a[2])};
}
inline void store3(double (*a)[8], const V3& v) {
  store(a[0], v.x);
  store(a[1], v.y);
  store(a[2], v.z);
}

}  // namespace rigid::physics::detail::RIGID_LANE_NS
