// The exact free rotor's cached step for general bodies (free_rotor.hpp: advance_rotor with a
// plan and RotorUpdate::kPinned; then q <- q dq, renormalised), several
// bodies at once: hybrid4's quiet general bodies. The kernel (rotor_lanes_kernel.cpp) restates the
// scalar code's arithmetic operation for operation, in its order (Eigen's SSE2 quaternion product
// and sum of squares included), so each lane's result is bit for bit what advance_rotor and
// integrate_exact.cpp's drift_cached give: a body steps to the same states whichever path, width,
// lane or thread steps it, and hybrid4's free bodies stay exactly exact_rotor4's (lanes_test's
// Lanes.FreeBodiesStepBitForBitAsTheScalarCode holds the kernel to it). Built per instruction set
// like hybrid_lanes.hpp's kernel; the dispatch, and what a block of plans and of states holds, are
// here.
#pragma once

#include <cstdint>

namespace rigid::physics::detail {

// Eight plans' fields as the kernel reads them, component-major: RotorPlan's amplitudes, phase
// constants, 1/G, its phase increment X and the psi integral's quadrature values at up to four
// nodes. k2 is RotorPlan::m. What the kernel needs of each plan besides (its node count, its case,
// its sign s, whether it is still) is a byte an entry beside the block (RotorPlans::flags,
// kRotorFlag* below): 26 lines of 64 B, 208 B an entry. The quadrature weights X w_i / 2 are not
// kept: the kernel makes them from X and the rule of n nodes (gauss_legendre.hpp), in the
// operations make_rotor_plan makes them in, to the same bits. Nor is what the plan derives from
// these by products alone (cn_bias, mS2, mSC, and cG = c / G, abG2 = a b / G^2 from 1/G:
// free_rotor.cpp, plan_core): the kernel derives it again, to the same bits.
struct alignas(64) RotorPlanLanes {
  static constexpr int kMax = 8;
  static constexpr int kNodes = 4;  // RotorPlan's quadrature nodes at most
  using L = double[kMax];
  L ia, ib, k2, mc, C, D, S, a, b, c, lin, iG, G, X;
  L Dn[kNodes], mS2n[kNodes], mSCn[kNodes];
};

// A plan's flags byte: its quadrature node count (RotorPlan::n, 0 to 4: 0 is a long step, with no
// nodes), its case (RotorPlan::case_b), RotorPlan::still, and its sign (RotorPlan::s, 1 or -1).
constexpr unsigned kRotorFlagNodes = 7u;
constexpr unsigned kRotorFlagCaseB = 8u;
constexpr unsigned kRotorFlagStill = 16u;
constexpr unsigned kRotorFlagNegative = 32u;  // s = -1

// Eight bodies' rotation state, component-major: q_WP, h_P.
struct alignas(64) RotorStateLanes {
  static constexpr int kMax = RotorPlanLanes::kMax;
  using L = double[kMax];
  L qw, qx, qy, qz;
  L m[3];
};

// Lanes [off, off + width) of the state and the plans (width: the kernel's), `flags` the block's
// eight flags bytes. The plans are read where they are stored (the tumbling group's
// GroupEntries::plan, rotor_plans.hpp).
namespace lanes8 {
void rotor_step(RotorStateLanes& st, const RotorPlanLanes& p, const unsigned char* flags, int off);
}
namespace lanes4 {
void rotor_step(RotorStateLanes& st, const RotorPlanLanes& p, const unsigned char* flags, int off);
}
namespace lanes2 {
void rotor_step(RotorStateLanes& st, const RotorPlanLanes& p, const unsigned char* flags, int off);
}

// The part that knows the groups (rotor_block_ready, rotor_gather_block, rotor_scatter_block) is
// declared in kernels.hpp.
// All eight lanes, by the kernel of `width` lanes (8, 4 or 2).
void rotor_step_lanes(int width, RotorStateLanes& st, const RotorPlanLanes& p,
                      const unsigned char* flags);

}  // namespace rigid::physics::detail
