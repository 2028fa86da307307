// The exact free rotation of quiet isotropic bodies with their cached increment
// (integrate_exact.cpp: q_WP <- q_WP dq, renormalised, dq = exp(h w) made when w last changed),
// four bodies at a time.
//
// Why: the step is ~40 flops a body, too few to hide the latency of one body's chain (product,
// sum of squares, the Newton factor) in the scalar code (Eigen's SSE2 path, two doubles at a
// time): perf on step_bench's sphere case put two thirds of the quiet isotropic body's step there.
// The kernel loads four bodies' quaternions where they are stored (Motion, structure of arrays
// would need every integrator changed), transposes them into four lanes of w, x, y, z, does the
// four products side by side and transposes back, about twice as fast as the scalar code. The
// increments, which only this step reads, are stored component by component already
// (IncrementBlock). AVX-512's gather and scatter were no faster than the scalar code; quaternions
// stored as structure of arrays would be faster still (bench/notes/step-kernels.md).
//
// The kernel restates the scalar arithmetic operation for operation (Eigen's SSE2 quaternion
// product and sum of squares, as rotor_lanes_kernel.cpp does; math.hpp's renormalize), so every
// body steps to the same bits by either path: lanes_test's
// Lanes.FreeBodiesStepBitForBitAsTheScalarCode holds it to the scalar code (RIGID_LANES=1). Built
// per instruction set like the other kernels (hybrid_lanes.hpp says why it includes no Eigen);
// hybrid4 and exact_rotor(4) call it through the width the World picked.
#pragma once

#include <cstddef>

namespace rigid::physics::detail {

// Four bodies' increments dq, component by component, as the kernel reads them (no transpose):
// the steady-spin group keeps them so (groups.hpp: SpinIncrements).
struct alignas(32) IncrementBlock {
  double x[4], y[4], z[4], w[4];
};

// n bodies (a multiple of 4): body k's quaternion (coefficients x, y, z, w, as Eigen stores them)
// at q + k * stride bytes, its increment in dq[k / 4], lane k % 4.
namespace lanes8 {
void iso_drift(char* q, std::ptrdiff_t stride, const IncrementBlock* dq, int n);
}
namespace lanes4 {
void iso_drift(char* q, std::ptrdiff_t stride, const IncrementBlock* dq, int n);
}
namespace lanes2 {
void iso_drift(char* q, std::ptrdiff_t stride, const IncrementBlock* dq, int n);
}

}  // namespace rigid::physics::detail
