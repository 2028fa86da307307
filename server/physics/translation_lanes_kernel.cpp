// Quiet bodies' exact translation, one body a vector (translation_lanes.hpp says why and what the
// arguments are). Compiled once per instruction set (server/physics/CMakeLists.txt); the SSE2
// build splits each vector in two.
#include <cstring>

#include "physics/translation_lanes.hpp"

namespace rigid::physics::detail::RIGID_LANE_NS {

namespace {

using D4 = double __attribute__((vector_size(32)));
using D2 = double __attribute__((vector_size(16)));

inline void load(D4& v, const void* p) {  // by reference: SSE2's ABI has no 256-bit register
  std::memcpy(&v, p, sizeof v);
}
inline void store(void* p, const D4& v) {
  std::memcpy(p, &v, sizeof v);
}

}  // namespace

namespace {

// kForce false: every body's force is +0.0 (the caller knows), so none is read; the acceleration
// is then the same g + inv_m * 0 for all, made once, to the same bits.
template <bool kForce>
void run(char* x, std::ptrdiff_t stride, const char* f, std::ptrdiff_t f_stride,
         const SharedTranslation& s, int n) {
  const D4 g = {s.g[0], s.g[1], s.g[2], 0.0}, inv_m = {s.inv_m[0], s.inv_m[1], s.inv_m[2], 0.0};
  const D4 E = {s.E, s.E, s.E, s.E}, p1 = {s.p1, s.p1, s.p1, s.p1}, q2 = {s.q2, s.q2, s.q2, s.q2};
  const D4 zero = {0.0, 0.0, 0.0, 0.0};
  const D4 a0 = g + inv_m * zero;
  for (int k = 0; k < n; ++k, x += stride) {
    D4 xv, v;
    load(xv, x);                      // x0 x1 x2 v0
    load(v, x + 3 * sizeof(double));  // v0 v1 v2 and the next double
    D4 a = a0;
    if constexpr (kForce) {
      // f0 f1 f2 0, from registers: three doubles copied into a zeroed vector in memory would go
      // through the stack, and the 256-bit load of narrower stores stalls (measured: the kernel
      // slower than the scalar code).
      D2 f01;
      double f2;
      std::memcpy(&f01, f, sizeof f01);
      std::memcpy(&f2, f + 2 * sizeof(double), sizeof f2);
      f += f_stride;
      const D2 f2_0 = {f2, 0.0};
      const D4 fw = __builtin_shufflevector(f01, f2_0, 0, 1, 2, 3);
      a = g + inv_m * fw;
    }
    const D4 x1 = xv + (p1 * v + q2 * a);  // lane 3 meaningless: overwritten below
    const D4 v1 = __builtin_shufflevector(E * v + p1 * a, v, 0, 1, 2, 7);  // lane 3 kept
    store(x, x1);
    store(x + 3 * sizeof(double), v1);  // after x1: v0 is v1's
  }
}

}  // namespace

void translate_quiet(char* x, std::ptrdiff_t stride, const char* f, std::ptrdiff_t f_stride,
                     const SharedTranslation& s, int n) {
  if (f != nullptr) {
    run<true>(x, stride, f, f_stride, s, n);
  } else {
    run<false>(x, stride, f, f_stride, s, n);
  }
}

}  // namespace rigid::physics::detail::RIGID_LANE_NS
