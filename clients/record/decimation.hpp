// rigid-record record --every N: which states to keep. With N > 1, a state is kept when its tick is
// a multiple of N publication periods (N x the scene's publish_every), so that the kept states stay
// evenly spaced in sim time even when the bus loses some; the states rigidd publishes between
// those (every period, and after a tick in which a new wrench took effect) are left out. With
// N = 1, every state is kept. Thread-safe: the scene is set from the bus's thread.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstdint>

#include "rigid/messages.hpp"

namespace rigid::record {

class Decimation {
 public:
  explicit Decimation(std::int64_t every) : every_(every) {}
  void scene(const rigid::SceneDescription& s) {
    period_.store(every_ > 1 ? every_ * std::max<std::int64_t>(1, s.publish_every) : 1,
                  std::memory_order_relaxed);
  }
  bool keep(std::int64_t tick) const {
    const std::int64_t p = period_.load(std::memory_order_relaxed);
    return p <= 1 || tick % p == 0;
  }

 private:
  std::int64_t every_;
  std::atomic<std::int64_t> period_{1};
};

}  // namespace rigid::record
