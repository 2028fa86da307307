// Quiet isotropic bodies' cached exact rotation, four at a time (iso_lanes.hpp says why and what
// the arguments are). Compiled once per instruction set (server/physics/CMakeLists.txt); the four
// lanes are one 256-bit vector of the compiler's vector extensions, which the SSE2 build splits
// in two. Each line below restates integrate_exact.cpp's q = q * dq; renormalize(q): the
// parenthesised groupings are those of Eigen's SSE2 quaternion product and sum of squares.
#include <cmath>
#include <cstdint>
#include <cstring>

#if defined(__x86_64__)
#include <immintrin.h>
#endif

#include "physics/iso_lanes.hpp"

namespace rigid::physics::detail::RIGID_LANE_NS {

namespace {

using D4 = double __attribute__((vector_size(32)));
using M4 = std::int64_t __attribute__((vector_size(32)));

// Rows a0..a3 (one body's x, y, z, w each) into columns (each component over the four bodies),
// and back: the same permutation both ways.
inline void transpose(D4& a0, D4& a1, D4& a2, D4& a3) {
  const D4 t0 = __builtin_shufflevector(a0, a1, 0, 4, 2, 6);  // x0 x1 z0 z1
  const D4 t1 = __builtin_shufflevector(a0, a1, 1, 5, 3, 7);  // y0 y1 w0 w1
  const D4 t2 = __builtin_shufflevector(a2, a3, 0, 4, 2, 6);  // x2 x3 z2 z3
  const D4 t3 = __builtin_shufflevector(a2, a3, 1, 5, 3, 7);  // y2 y3 w2 w3
  a0 = __builtin_shufflevector(t0, t2, 0, 1, 4, 5);
  a1 = __builtin_shufflevector(t1, t3, 0, 1, 4, 5);
  a2 = __builtin_shufflevector(t0, t2, 2, 3, 6, 7);
  a3 = __builtin_shufflevector(t1, t3, 2, 3, 6, 7);
}

// Whether every lane is set: one test instruction where the instruction set has it (a branch per
// lane showed in perf; with the one test, step_bench's sphere went 4.9-5.7 -> 4.1-5.2 ns).
inline bool all(const M4& m) {
#if defined(__AVX__)
  return _mm256_movemask_pd(reinterpret_cast<__m256d>(m)) == 0xF;
#else
  return (m[0] & m[1] & m[2] & m[3]) != 0;
#endif
}

// By reference: the SSE2 build may not pass 256-bit vectors by value (its ABI has no such
// register).
inline void load(D4& v, const void* p) {
  std::memcpy(&v, p, sizeof v);
}
inline void store(void* p, const D4& v) {
  std::memcpy(p, &v, sizeof v);
}

}  // namespace

void iso_drift(char* q, std::ptrdiff_t stride, const IncrementBlock* dq, int n) {
  for (int k = 0; k < n; k += 4, q += 4 * stride, ++dq) {
    D4 ax, ay, az, aw, bx, by, bz, bw;
    load(ax, q);
    load(ay, q + stride);
    load(az, q + 2 * stride);
    load(aw, q + 3 * stride);
    transpose(ax, ay, az, aw);
    load(bx, dq->x);
    load(by, dq->y);
    load(bz, dq->z);
    load(bw, dq->w);
    // Eigen's quaternion product a b, SSE2 path (Geometry_SIMD.h), terms paired as there.
    D4 w = (aw * bw - ay * by) - (az * bz + ax * bx);
    D4 x = (aw * bx + ay * bz) - (az * by - ax * bw);
    D4 y = (aw * by + ay * bw) + (az * bx - ax * bz);
    D4 z = (aw * bz - ay * bx) + (az * bw + ax * by);
    // math.hpp's renormalize; Eigen's squaredNorm sums the coefficients (x, y, z, w) in two
    // packets: (x^2 + z^2) + (y^2 + w^2).
    const D4 n2 = (x * x + z * z) + (y * y + w * w);
    const D4 e = n2 - 1.0;
    const M4 near = (e < 1e-8) & (e > -1e-8);
    const D4 f = 1.5 - 0.5 * n2;
    D4 rx = x * f, ry = y * f, rz = z * f, rw = w * f;
    for (int l = 0; !all(near) && l < 4; ++l) {
      if (near[l] == 0) {  // far from 1: a full normalisation, as the scalar code
        const double s = std::sqrt(n2[l]);
        rx[l] = x[l] / s;
        ry[l] = y[l] / s;
        rz[l] = z[l] / s;
        rw[l] = w[l] / s;
      }
    }
    transpose(rx, ry, rz, rw);  // back to one body a vector
    store(q, rx);
    store(q + stride, ry);
    store(q + 2 * stride, rz);
    store(q + 3 * stride, rw);
  }
}

}  // namespace rigid::physics::detail::RIGID_LANE_NS
