#include "physics/rotor_plans.hpp"

#include <cassert>
#include <limits>
#include <utility>

#include "physics/gauss_legendre.hpp"

namespace rigid::physics::detail {

static_assert(RotorPlanLanes::kNodes == sizeof(RotorPlan::w) / sizeof(double));
static_assert(RotorPlanLanes::kNodes <= kRotorFlagNodes);

void RotorPlans::push_back() {
  if (size_ % kBlock == 0) {
    blocks_.emplace_back();
    flags_.resize(flags_.size() + kBlock);
  }
  ++size_;
  set(size_ - 1, RotorPlan{});
}

namespace {
// A long step's constants, where a short step keeps its nodes: Dn[0..3] and mS2n[0..2] of its lane.
enum LongSlot { kQ, kIsr, kSq, kQm3, kK, kJc, kClosed };
double& long_slot(RotorPlanLanes& L, int k, int l) {
  return k < 4 ? L.Dn[k][l] : L.mS2n[k - 4][l];
}
double long_slot(const RotorPlanLanes& L, int k, int l) {
  return k < 4 ? L.Dn[k][l] : L.mS2n[k - 4][l];
}
}  // namespace

RotorPlan RotorPlans::get(int i) const {
  const RotorPlanLanes& L = blocks_[static_cast<std::size_t>(i / kBlock)];
  const int l = i % kBlock;
  const unsigned f = flags_[static_cast<std::size_t>(i)];
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  RotorPlan p;
  p.still = (f & kRotorFlagStill) != 0;
  p.case_b = (f & kRotorFlagCaseB) != 0;
  p.s = (f & kRotorFlagNegative) != 0 ? -1.0 : 1.0;
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
  p.iG = L.iG[l];
  p.lin = L.lin[l];
  p.abG2 = p.a * p.b * p.iG * p.iG;  // as plan_core makes them
  p.cG = p.c * p.iG;
  p.S = L.S[l];
  p.C = L.C[l];
  p.D = L.D[l];
  p.mS2 = p.m * p.S * p.S;
  p.mSC = p.m * p.S * p.C;
  p.Cm1 = kNaN;
  p.Dm1 = kNaN;
  p.X = L.X[l];
  p.n = static_cast<int>(f & kRotorFlagNodes);
  // set keeps n as make_rotor_plan gives it: 0 or the node count of a rule of kRotorRule.
  assert(p.n == 0 || (p.n >= 2 && p.n <= RotorPlanLanes::kNodes && kRotorRule[p.n] != nullptr));
  for (int k = 0; k < RotorPlanLanes::kNodes; ++k)
    p.w[k] = p.Dn[k] = p.mS2n[k] = p.mSCn[k] = kNaN;
  if (p.n > 0) {
    const GaussLegendre& rule = *kRotorRule[p.n];
    for (int k = 0; k < p.n; ++k) {
      p.w[k] = 0.5 * p.X * rule.w[k];  // as make_rotor_plan makes it
      p.Dn[k] = L.Dn[k][l];
      p.mS2n[k] = L.mS2n[k][l];
      p.mSCn[k] = L.mSCn[k][l];
    }
    p.q = p.isr = p.sq = p.qm3 = p.K = p.Jc = kNaN;
    p.closed = false;
  } else {
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
  // n is 0 or a rule's node count (make_rotor_plan); kRotorRule has one for each n > 0 kept.
  flags_[static_cast<std::size_t>(i)] = static_cast<unsigned char>(
      (static_cast<unsigned>(p.n) & kRotorFlagNodes) | (p.case_b ? kRotorFlagCaseB : 0u) |
      (p.still ? kRotorFlagStill : 0u) | (p.s < 0.0 ? kRotorFlagNegative : 0u));
  L.a[l] = p.a;
  L.b[l] = p.b;
  L.c[l] = p.c;
  L.ia[l] = p.ia;
  L.ib[l] = p.ib;
  L.k2[l] = p.m;
  L.mc[l] = p.mc;
  L.G[l] = p.G;
  L.iG[l] = p.iG;
  L.lin[l] = p.lin;
  L.S[l] = p.S;
  L.C[l] = p.C;
  L.D[l] = p.D;
  L.X[l] = p.X;
  for (int k = 0; k < RotorPlanLanes::kNodes; ++k) {
    L.Dn[k][l] = p.Dn[k];
    L.mS2n[k][l] = p.mS2n[k];
    L.mSCn[k][l] = p.mSCn[k];
  }
  if (p.n == 0) {
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
