// Gathers general bodies' rotation state and cached rotor plans into a RotorBatch, picks the
// kernel for the width, scatters the results back (rotor_lanes.hpp).
#include "physics/rotor_lanes.hpp"

#include "physics/model.hpp"

namespace rigid::physics::detail {

static_assert(RotorBatch::kNodes == sizeof(RotorPlan::w) / sizeof(double));

bool rotor_lane_ready(const GenGroup& g, int i) {
  const RotorPlan& p = g.plan[i];
  return g.plan_ok[i] && !p.still && p.n > 0;
}

void rotor_gather(const GenGroup& g, int i, int l, RotorBatch& b) {
  const Motion& mo = g.motion[i];
  b.qw[l] = mo.q.w();
  b.qx[l] = mo.q.x();
  b.qy[l] = mo.q.y();
  b.qz[l] = mo.q.z();
  for (int k = 0; k < 3; ++k)
    b.m[k][l] = mo.spin[k];
  const Quat& ax = g.axis[i];
  b.aw[l] = ax.w();
  b.ax[l] = ax.x();
  b.ay[l] = ax.y();
  b.az[l] = ax.z();
  const RotorPlan& p = g.plan[i];
  b.case_b[l] = p.case_b ? -1 : 0;
  b.s[l] = p.s;
  b.ia[l] = p.ia;
  b.ib[l] = p.ib;
  b.cn_bias[l] = p.cn_bias;
  b.k2[l] = p.m;
  b.mc[l] = p.mc;
  b.cG[l] = p.cG;
  b.mS2[l] = p.mS2;
  b.C[l] = p.C;
  b.D[l] = p.D;
  b.S[l] = p.S;
  b.mSC[l] = p.mSC;
  b.a[l] = p.a;
  b.b[l] = p.b;
  b.c[l] = p.c;
  b.lin[l] = p.lin;
  b.abG2[l] = p.abG2;
  b.G[l] = p.G;
  for (int k = 0; k < RotorBatch::kNodes; ++k) {
    b.node[k][l] = k < p.n ? -1 : 0;
    b.w[k][l] = p.w[k];
    b.Dn[k][l] = p.Dn[k];
    b.mS2n[k][l] = p.mS2n[k];
    b.mSCn[k][l] = p.mSCn[k];
  }
}

void rotor_scatter(const RotorBatch& b, int l, GenGroup& g, int i) {
  Motion& mo = g.motion[i];
  mo.q = Quat(b.qw[l], b.qx[l], b.qy[l], b.qz[l]);
  mo.spin = Vec3(b.m[0][l], b.m[1][l], b.m[2][l]);
  g.axis[i] = Quat(b.aw[l], b.ax[l], b.ay[l], b.az[l]);
}

void rotor_step_lanes(int width, RotorBatch& b) {
  switch (width) {
    case 8:
      lanes8::rotor_step(b);
      break;
    case 4:
      lanes4::rotor_step(b);
      break;
    default:
      lanes2::rotor_step(b);
      break;
  }
}

}  // namespace rigid::physics::detail
