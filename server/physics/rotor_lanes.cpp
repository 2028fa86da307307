// Gathers a block of general bodies' rotation state into lanes, picks the kernel for the width,
// scatters the results back (rotor_lanes.hpp); the plans stay where they are.
#include "physics/rotor_lanes.hpp"

#include <cstring>

#include "physics/kernels.hpp"

namespace rigid::physics::detail {

bool rotor_block_ready(const TumblingGroup& g, int block) {
  // plan_ok's eight bytes as one word (each 0 or 1).
  static_assert(RotorPlans::kBlock == 8);
  std::uint64_t ok;
  std::memcpy(&ok, g.entries.plan_ok.data() + static_cast<std::size_t>(block) * RotorPlans::kBlock,
              sizeof ok);
  return ok == 0x0101010101010101u && g.entries.plan.block_ready(block);
}

void rotor_gather_block(const TumblingGroup& g, int block, RotorStateLanes& st) {
  const int first = block * RotorPlans::kBlock;
  for (int l = 0; l < RotorPlans::kBlock; ++l) {
    const Motion& mo = g.motion(first + l);
    st.qw[l] = mo.q.w();
    st.qx[l] = mo.q.x();
    st.qy[l] = mo.q.y();
    st.qz[l] = mo.q.z();
    for (int k = 0; k < 3; ++k)
      st.m[k][l] = mo.spin[k];
  }
}

void rotor_scatter_block(const RotorStateLanes& st, int block, const TumblingGroup& g) {
  const int first = block * RotorPlans::kBlock;
  for (int l = 0; l < RotorPlans::kBlock; ++l) {
    Motion& mo = g.motion(first + l);
    mo.q = Quat(st.qw[l], st.qx[l], st.qy[l], st.qz[l]);
    mo.spin = Vec3(st.m[0][l], st.m[1][l], st.m[2][l]);
  }
}

void rotor_step_lanes(int width, RotorStateLanes& st, const RotorPlanLanes& p,
                      const unsigned char* flags) {
  for (int off = 0; off < RotorPlanLanes::kMax; off += width) {
    switch (width) {
      case 8:
        lanes8::rotor_step(st, p, flags, off);
        break;
      case 4:
        lanes4::rotor_step(st, p, flags, off);
        break;
      default:
        lanes2::rotor_step(st, p, flags, off);
        break;
    }
  }
}

}  // namespace rigid::physics::detail
