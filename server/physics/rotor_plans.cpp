#include "physics/rotor_plans.hpp"

#include <limits>
#include <utility>

namespace rigid::physics::detail {

static_assert(RotorPlanLanes::kNodes == sizeof(RotorPlan::w) / sizeof(double));
// A long step's eight constants fit in the slots of w and Dn.
static_assert(2 * RotorPlanLanes::kNodes >= 8);

void RotorPlans::push_back() {
  if (size_ % kBlock == 0) blocks_.emplace_back();
  ++size_;
  set(size_ - 1, RotorPlan{});
}

namespace {
// A long step's constants, where a short step keeps its nodes: w[0..3] and Dn[0..3] of its lane.
enum LongSlot { kX, kQ, kIsr, kSq, kQm3, kK, kJc, kClosed };
double& long_slot(RotorPlanLanes& L, int k, int l) {
  return k < 4 ? L.w[k][l] : L.Dn[k - 4][l];
}
double long_slot(const RotorPlanLanes& L, int k, int l) {
  return k < 4 ? L.w[k][l] : L.Dn[k - 4][l];
}
}  // namespace

RotorPlan RotorPlans::get(int i) const {
  const RotorPlanLanes& L = blocks_[static_cast<std::size_t>(i / kBlock)];
  const int l = i % kBlock;
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  RotorPlan p;
  p.still = L.still[l] != 0;
  p.case_b = L.case_b[l] != 0;
  p.s = L.s[l];
  p.a = L.a[l];
  p.b = L.b[l];
  p.c = L.c[l];
  p.ia = L.ia[l];
  p.ib = L.ib[l];
  p.ic = kNaN;
  p.cn_bias = p.a > 0.0 ? 0.0 : 1.0;  // derived as plan_core does (rotor_lanes.hpp)
  p.m = L.k2[l];
  p.mc = L.mc[l];
  p.G = L.G[l];
  p.lin = L.lin[l];
  p.abG2 = L.abG2[l];
  p.cG = L.cG[l];
  p.S = L.S[l];
  p.C = L.C[l];
  p.D = L.D[l];
  p.mS2 = p.m * p.S * p.S;
  p.mSC = p.m * p.S * p.C;
  p.Cm1 = kNaN;
  p.Dm1 = kNaN;
  p.n = L.n[l];
  if (p.n > 0) {
    for (int k = 0; k < RotorPlanLanes::kNodes; ++k) {
      p.w[k] = L.w[k][l];
      p.Dn[k] = L.Dn[k][l];
      p.mS2n[k] = L.mS2n[k][l];
      p.mSCn[k] = L.mSCn[k][l];
    }
    p.X = p.q = p.isr = p.sq = p.qm3 = p.K = p.Jc = kNaN;
    p.closed = false;
  } else {
    p.X = long_slot(L, kX, l);
    p.q = long_slot(L, kQ, l);
    p.isr = long_slot(L, kIsr, l);
    p.sq = long_slot(L, kSq, l);
    p.qm3 = long_slot(L, kQm3, l);
    p.K = long_slot(L, kK, l);
    p.Jc = long_slot(L, kJc, l);
    p.closed = long_slot(L, kClosed, l) != 0.0;
  }
  return p;
}

void RotorPlans::set(int i, const RotorPlan& p) {
  RotorPlanLanes& L = blocks_[static_cast<std::size_t>(i / kBlock)];
  const int l = i % kBlock;
  L.still[l] = p.still ? 1 : 0;
  L.case_b[l] = p.case_b ? -1 : 0;
  L.s[l] = p.s;
  L.a[l] = p.a;
  L.b[l] = p.b;
  L.c[l] = p.c;
  L.ia[l] = p.ia;
  L.ib[l] = p.ib;
  L.k2[l] = p.m;
  L.mc[l] = p.mc;
  L.G[l] = p.G;
  L.lin[l] = p.lin;
  L.abG2[l] = p.abG2;
  L.cG[l] = p.cG;
  L.S[l] = p.S;
  L.C[l] = p.C;
  L.D[l] = p.D;
  L.n[l] = p.n;
  for (int k = 0; k < RotorPlanLanes::kNodes; ++k) {
    L.w[k][l] = p.w[k];
    L.Dn[k][l] = p.Dn[k];
    L.mS2n[k][l] = p.mS2n[k];
    L.mSCn[k][l] = p.mSCn[k];
  }
  if (p.n == 0) {
    long_slot(L, kX, l) = p.X;
    long_slot(L, kQ, l) = p.q;
    long_slot(L, kIsr, l) = p.isr;
    long_slot(L, kSq, l) = p.sq;
    long_slot(L, kQm3, l) = p.qm3;
    long_slot(L, kK, l) = p.K;
    long_slot(L, kJc, l) = p.Jc;
    long_slot(L, kClosed, l) = p.closed ? 1.0 : 0.0;
  }
}

void RotorPlans::swap(int i, int j) {
  if (i == j) return;
  const RotorPlan pi = get(i);
  set(i, get(j));
  set(j, pi);
}

}  // namespace rigid::physics::detail
