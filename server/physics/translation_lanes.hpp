// The exact translation of bodies with nothing turning them (translation.hpp's translate with a
// constant acceleration a = g + (1/m) f_W), one body a 256-bit vector: the quiet point masses
// and isotropic bodies of hybrid4 and exact_rotor(4), for the consecutive bodies that share one
// set of translation parameters (GroupParams::linear). (Axisymmetric and general bodies translate
// body by body beside their longer drifts: integrate_exact.cpp says why.)
//
// Why: Eigen keeps a Vec3 in scalars and pairs, so the scalar code spends about as long moving
// x, v and f_W between registers as computing; here x (with v's first component) and v (with the
// spin's first) each load as one vector and store as one, the lane beyond the three kept as it
// was: about twice as fast as the scalar code (bench/notes/step-kernels.md).
//
// The arithmetic is the scalar code's per component, in its order (a_c = g_c + (1/m)_c f_c;
// x_c += p1 v_c + q2 a_c; v_c = E v_c + p1 a_c), so a body steps to the same bits by either path
// (lanes_test: Lanes.FreeBodiesStepBitForBitAsTheScalarCode). Built per instruction set like the
// other kernels (hybrid_lanes.hpp says why it includes no Eigen).
#pragma once

#include <cstddef>

namespace rigid::physics::detail {

// What n consecutive bodies share: gravity and 1/m per axis, and the step's coefficients.
struct SharedTranslation {
  double g[3], inv_m[3];
  double E, p1, q2;
};

// n bodies: body k's position at x + k * stride bytes, its velocity the three doubles after it
// and then at least one more double (Motion's spin); its force in W at f + k * f_stride bytes, or
// +0.0 for every body when f is null (then nothing is read for it).
namespace lanes8 {
void translate_quiet(char* x, std::ptrdiff_t stride, const char* f, std::ptrdiff_t f_stride,
                     const SharedTranslation& s, int n);
}
namespace lanes4 {
void translate_quiet(char* x, std::ptrdiff_t stride, const char* f, std::ptrdiff_t f_stride,
                     const SharedTranslation& s, int n);
}
namespace lanes2 {
void translate_quiet(char* x, std::ptrdiff_t stride, const char* f, std::ptrdiff_t f_stride,
                     const SharedTranslation& s, int n);
}

}  // namespace rigid::physics::detail
