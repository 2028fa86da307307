// Wakes a thread that waits for work, with a timeout: the transport threads ring it after queuing
// a command, and the loop waits on it whenever it has nothing to step (paused, lockstep, or fast
// mode paused), so a command is handled as soon as it arrives without polling. A Linux futex: no
// allocation and no lock on either side.
#pragma once

#include <atomic>
#include <cstdint>

namespace rigid::loop {

class Doorbell {
 public:
  // The current ring count; pass it to wait_until to sleep only if no ring came since.
  std::uint32_t count() const { return count_.load(std::memory_order_acquire); }
  void ring();
  // Returns when the count differs from `seen`, at CLOCK_MONOTONIC `deadline_ns`, or on a
  // spurious wake-up; the caller re-checks what it waits for.
  void wait_until(std::uint32_t seen, std::int64_t deadline_ns) const;

 private:
  std::atomic<std::uint32_t> count_{0};
};

}  // namespace rigid::loop
