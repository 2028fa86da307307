// hybrid4's loaded bodies, several at once: the triple-jump composition of integrate_exact.cpp
// (kick, cheap split drift, kick; TripleJump in model.hpp) for the loaded run of the tumbling and
// precession groups, over lanes of W bodies. hybrid_lanes.cpp gathers W bodies from the groups'
// arrays into a LaneBatch (structure of arrays), runs a kernel on it and scatters the result back.
// The kernel (hybrid_lanes_kernel.cpp) is compiled once per instruction set, 8 lanes with AVX-512,
// 4 with AVX2, 2 with the x86-64 baseline (SSE2), and picked at run time for the CPU. It includes
// nothing but this header, lanes.hpp (whose code lives in the kernel's own namespace), the
// standard C headers and the compiler's intrinsics (always inlined): no inline function of a
// shared header is compiled with an instruction set the CPU may lack (the linker could keep that
// copy for everyone).
//
// Why the states do not depend on the CPU, the thread count or where a body falls in a batch: each
// lane is one body's arithmetic, the same IEEE operations in the same order in every lane and every
// build (+ - * / sqrt only, no fused multiply-add: the kernel is built with -ffp-contract=off; the
// rare branches run per lane through scalar code and libm), and a batch that is not full is padded
// with copies of a real body and only its real lanes are written back. So a body steps to the same
// bits whichever kernel, thread and lane step it.
#pragma once

#include <cstdint>

namespace rigid::physics::detail {

// Up to 8 bodies, component-major so that a lane vector loads from one place.
struct alignas(64) LaneBatch {
  static constexpr int kMax = 8;
  using L = double[kMax];
  // State: q_WP, p_WBo, v_WBo, h_P.
  L qw, qx, qy, qz;
  L x[3], v[3], m[3];
  // Parameters: gravity, 1/m per axis, principal 1/I, angular drag rates per P axis, translation
  // coefficients for the stage sizes kForced0 ([0]) and kForced1 ([1]).
  L g[3], inv_m[3], inv_I[3], decay[3];
  L E[2], p1[2], p2[2], q2[2], q3[2];
  // Loads (loads.hpp): lane masks (-1 / 0) for the flags that add terms, then the terms.
  std::int64_t body_force[kMax], world_torque[kMax], lever[kMax];
  L f_W[3], f_P[3], tau_P[3], tau_W[3];
  L fr[3][3];
};

// The composition's constants for one step: stage sizes c_k h, which translation coefficients
// each stage uses (0: kForced0, 1: kForced1), and the drift (general: split, else axisymmetric).
struct LaneStages {
  static constexpr int kStages = 3;
  double s[kStages];
  int size[kStages];
  bool general;
};

// The kernels by width: step the first `W` lanes of b (all of them hold bodies: padding is the
// caller's) by one composition.
namespace lanes8 {
void step(LaneBatch& b, const LaneStages& st);
}
namespace lanes4 {
void step(LaneBatch& b, const LaneStages& st);
}
namespace lanes2 {
void step(LaneBatch& b, const LaneStages& st);
}

// The widest kernel this CPU runs (8, 4 or 2), or a narrower one named by RIGID_LANES=2|4 in the
// environment (tests compare the kernels; a width the CPU cannot run is not taken); RIGID_LANES=1:
// no lanes, every body through the scalar code (tests hold the kernels to it). Read when a World
// is built, kept in Model::lanes.
int pick_lane_width();

// The part that knows the groups (hybrid_loaded_lanes) is declared in kernels.hpp.

}  // namespace rigid::physics::detail
