// The exact free rotor's cached step for general bodies (free_rotor.hpp: advance_rotor with a
// plan, RotorUpdate::kPinned and the carried axis frame; then q <- q dq, renormalised), several
// bodies at once: hybrid4's quiet general bodies. The kernel (rotor_lanes_kernel.cpp) restates the
// scalar code's arithmetic operation for operation, in its order (Eigen's SSE2 quaternion product
// and sum of squares included), so each lane's result is bit for bit what advance_rotor and
// integrate_exact.cpp's drift_cached give: a body steps to the same states whichever path, width,
// lane or thread steps it, and hybrid4's free bodies stay exactly exact_rotor4's (lanes_test's
// Lanes.FreeBodiesStepBitForBitAsTheScalarCode holds the kernel to it). Built per instruction set
// like hybrid_lanes.hpp's kernel; the dispatch and what a batch holds are here.
#pragma once

#include <cstdint>

namespace rigid::physics::detail {

// Up to 8 bodies' rotation state and rotor plans, component-major.
struct alignas(64) RotorBatch {
  static constexpr int kMax = 8;
  static constexpr int kNodes = 4;  // RotorPlan's quadrature nodes at most
  using L = double[kMax];
  // State: q_WP, h_P, and the carried end-of-step axis frame (GenGroup::axis).
  L qw, qx, qy, qz;
  L m[3];
  L aw, ax, ay, az;
  // The plan (RotorPlan, free_rotor.hpp): its case, phase constants and amplitudes, and the
  // quadrature of the psi integral; node[i] is -1 where the plan has more than i nodes.
  std::int64_t case_b[kMax];
  L s, ia, ib, cn_bias, k2, mc, cG, mS2, C, D, S, mSC, a, b, c, lin, abG2, G;
  std::int64_t node[kNodes][kMax];
  L w[kNodes], Dn[kNodes], mS2n[kNodes], mSCn[kNodes];
};

namespace lanes8 {
void rotor_step(RotorBatch& b);
}
namespace lanes4 {
void rotor_step(RotorBatch& b);
}
namespace lanes2 {
void rotor_step(RotorBatch& b);
}

struct GenGroup;
// Whether entry i's cached plan can step in a batch (made, not still, a short step with nodes).
bool rotor_lane_ready(const GenGroup& g, int i);
// Entry i into lane l, and back.
void rotor_gather(const GenGroup& g, int i, int l, RotorBatch& b);
void rotor_scatter(const RotorBatch& b, int l, GenGroup& g, int i);
// The kernel of `width` lanes (8, 4 or 2) on the first `width` lanes of b.
void rotor_step_lanes(int width, RotorBatch& b);

}  // namespace rigid::physics::detail
