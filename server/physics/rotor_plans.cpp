#include "physics/rotor_plans.hpp"

#include <utility>

namespace rigid::physics::detail {

static_assert(RotorPlanLanes::kNodes == sizeof(RotorPlan::w) / sizeof(double));

void RotorPlans::push_back() {
  if (size_ % kBlock == 0) blocks_.emplace_back();
  ++size_;
  set(size_ - 1, RotorPlan{});
}

RotorPlan RotorPlans::get(int i) const {
  const Block& b = blocks_[static_cast<std::size_t>(i / kBlock)];
  const RotorPlanLanes& L = b.lanes;
  const int l = i % kBlock;
  RotorPlan p;
  p.still = b.still[l] != 0;
  p.case_b = L.case_b[l] != 0;
  p.s = L.s[l];
  p.a = L.a[l];
  p.b = L.b[l];
  p.c = L.c[l];
  p.ia = L.ia[l];
  p.ib = L.ib[l];
  p.ic = b.ic[l];
  p.cn_bias = L.cn_bias[l];
  p.m = L.k2[l];
  p.mc = L.mc[l];
  p.G = L.G[l];
  p.lin = L.lin[l];
  p.abG2 = L.abG2[l];
  p.cG = L.cG[l];
  p.S = L.S[l];
  p.C = L.C[l];
  p.D = L.D[l];
  p.mS2 = L.mS2[l];
  p.mSC = L.mSC[l];
  p.Cm1 = b.Cm1[l];
  p.Dm1 = b.Dm1[l];
  p.X = b.X[l];
  p.n = b.n[l];
  for (int k = 0; k < RotorPlanLanes::kNodes; ++k) {
    p.w[k] = L.w[k][l];
    p.Dn[k] = L.Dn[k][l];
    p.mS2n[k] = L.mS2n[k][l];
    p.mSCn[k] = L.mSCn[k][l];
  }
  p.closed = b.closed[l] != 0;
  p.q = b.q[l];
  p.isr = b.isr[l];
  p.sq = b.sq[l];
  p.qm3 = b.qm3[l];
  p.K = b.K[l];
  p.Jc = b.Jc[l];
  return p;
}

void RotorPlans::set(int i, const RotorPlan& p) {
  Block& b = blocks_[static_cast<std::size_t>(i / kBlock)];
  RotorPlanLanes& L = b.lanes;
  const int l = i % kBlock;
  b.still[l] = p.still ? 1 : 0;
  L.case_b[l] = p.case_b ? -1 : 0;
  L.s[l] = p.s;
  L.a[l] = p.a;
  L.b[l] = p.b;
  L.c[l] = p.c;
  L.ia[l] = p.ia;
  L.ib[l] = p.ib;
  b.ic[l] = p.ic;
  L.cn_bias[l] = p.cn_bias;
  L.k2[l] = p.m;
  L.mc[l] = p.mc;
  L.G[l] = p.G;
  L.lin[l] = p.lin;
  L.abG2[l] = p.abG2;
  L.cG[l] = p.cG;
  L.S[l] = p.S;
  L.C[l] = p.C;
  L.D[l] = p.D;
  L.mS2[l] = p.mS2;
  L.mSC[l] = p.mSC;
  b.Cm1[l] = p.Cm1;
  b.Dm1[l] = p.Dm1;
  b.X[l] = p.X;
  b.n[l] = p.n;
  for (int k = 0; k < RotorPlanLanes::kNodes; ++k) {
    L.node[k][l] = k < p.n ? -1 : 0;
    L.w[k][l] = p.w[k];
    L.Dn[k][l] = p.Dn[k];
    L.mS2n[k][l] = p.mS2n[k];
    L.mSCn[k][l] = p.mSCn[k];
  }
  b.closed[l] = p.closed ? 1 : 0;
  b.q[l] = p.q;
  b.isr[l] = p.isr;
  b.sq[l] = p.sq;
  b.qm3[l] = p.qm3;
  b.K[l] = p.K;
  b.Jc[l] = p.Jc;
}

void RotorPlans::swap(int i, int j) {
  if (i == j) return;
  const RotorPlan pi = get(i);
  set(i, get(j));
  set(j, pi);
}

}  // namespace rigid::physics::detail
