// The cached free-rotor plans of the general bodies (RotorPlan, free_rotor.hpp), stored the way
// the lanes kernel reads them: eight entries to a block, each field of the eight side by side
// (structure of arrays). A block of eight quiet bodies whose plans are ready is stepped straight
// from its block (rotor_lanes.hpp), instead of copying ~45 fields of each body's plan into a batch
// one lane at a time every step, which would cost the quiet general body more than the kernel's
// arithmetic (bench/notes/step-kernels.md, "Rotor plans stored eight to a block").
//
// A cached plan is only ever stepped with RotorUpdate::kPinned (integrate_exact.cpp's
// drift_cached, and the kernel), so the store keeps what that reads and nothing else: 208 B an
// entry and a flags byte (node count, case, still, sign), where the whole RotorPlan takes 384
// (bench/physics/memory_bench.cpp; issue 13's budget of 500 B a body). What RotorUpdate::kIncrement
// alone reads (ic, Cm1, Dm1) is not kept: get gives NaN there; what plan_core derives by products
// alone (cn_bias, mS2, mSC, cG, abG2) get derives again, and the quadrature weights w_i = X
// w_i(rule) / 2 too, from X and the rule of n nodes (gauss_legendre.hpp), as make_rotor_plan does.
// A long step (no quadrature nodes) keeps its closed-form constants (q, isr, sq, qm3, K, Jc,
// closed) in the node slots it does not use; a short step reads none of them, and get gives NaN for
// them, as for the nodes past n. advance_rotor(get(i), ..., kPinned) steps bit for bit as with the
// plan set.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "physics/free_rotor.hpp"
#include "physics/rotor_lanes.hpp"

namespace rigid::physics::detail {

class RotorPlans {
 public:
  static constexpr int kBlock = RotorPlanLanes::kMax;
  int size() const { return size_; }
  // Appends a default RotorPlan.
  void push_back();
  // Entry i's plan as RotorUpdate::kPinned reads it (NaN in the fields not kept, see above).
  RotorPlan get(int i) const;
  void set(int i, const RotorPlan& p);
  void swap(int i, int j);
  // Whether entry i's plan can step in the lanes kernel: something moves and the step is short
  // (its quadrature nodes are cached). Says nothing of whether the plan is still valid.
  bool lane_ready(int i) const {
    const unsigned f = flags_[static_cast<std::size_t>(i)];
    return (f & kRotorFlagStill) == 0 && (f & kRotorFlagNodes) > 0;
  }
  // Whether all eight plans of block k (entries 8k .. 8k + 7, all of which exist) can step in the
  // lanes kernel, as lane_ready says of each: one pass over the block's flags, no branch a lane.
  bool block_ready(int block) const {
    // The eight bytes as one word: no still bit set, and some node bit set in every byte.
    static_assert(kBlock == 8);
    constexpr std::uint64_t kOnes = 0x0101010101010101u;
    std::uint64_t f;
    std::memcpy(&f, flags(block), sizeof f);
    const std::uint64_t nodes = f & (kOnes * kRotorFlagNodes);
    const std::uint64_t some = (nodes | (nodes >> 1) | (nodes >> 2)) & kOnes;
    return (f & (kOnes * kRotorFlagStill)) == 0 && some == kOnes;
  }
  // Asks the CPU to bring block k's kernel fields into the cache (a hint; nothing if k is past
  // the end): the kernel reads them in its own order, not the memory's, which the hardware
  // prefetcher does not follow.
  void prefetch(int block) const {
    if (block >= static_cast<int>(blocks_.size())) return;
    const char* p = reinterpret_cast<const char*>(&blocks_[static_cast<std::size_t>(block)]);
    for (std::size_t k = 0; k < sizeof(RotorPlanLanes); k += 64)
      __builtin_prefetch(p + k);
  }
  const RotorPlanLanes& lanes(int block) const { return blocks_[static_cast<std::size_t>(block)]; }
  // Block k's eight flags bytes (kRotorFlag*, rotor_lanes.hpp).
  const unsigned char* flags(int block) const {
    return flags_.data() + static_cast<std::size_t>(block) * kBlock;
  }

 private:
  static_assert(sizeof(RotorPlanLanes) == 26 * 64, "208 B an entry");
  std::vector<RotorPlanLanes> blocks_;
  // An entry's flags byte, kBlock to a block (those of a block's entries not yet pushed: 0).
  std::vector<unsigned char> flags_;
  int size_ = 0;
};

}  // namespace rigid::physics::detail
