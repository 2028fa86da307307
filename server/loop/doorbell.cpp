#include "loop/doorbell.hpp"

#include <linux/futex.h>
#include <sys/syscall.h>
#include <time.h>
#include <unistd.h>

#include <climits>

namespace rigid::loop {
namespace {

static_assert(sizeof(std::atomic<std::uint32_t>) == sizeof(std::uint32_t));

// The futex word is the atomic's storage (same size and representation, lock-free).
std::uint32_t* word(const std::atomic<std::uint32_t>& a) {
  return reinterpret_cast<std::uint32_t*>(const_cast<std::atomic<std::uint32_t>*>(&a));
}

}  // namespace

void Doorbell::ring() {
  count_.fetch_add(1, std::memory_order_release);
  syscall(SYS_futex, word(count_), FUTEX_WAKE_PRIVATE, INT_MAX, nullptr, nullptr, 0);
}

void Doorbell::wait_until(std::uint32_t seen, std::int64_t deadline_ns) const {
  if (count_.load(std::memory_order_acquire) != seen) return;
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(deadline_ns / 1'000'000'000);
  ts.tv_nsec = static_cast<long>(deadline_ns % 1'000'000'000);
  // FUTEX_WAIT_BITSET takes an absolute CLOCK_MONOTONIC deadline; it returns at once if the
  // word is no longer `seen` (a ring between the load above and this call is not lost).
  syscall(SYS_futex, word(count_), FUTEX_WAIT_BITSET_PRIVATE, seen, &ts, nullptr,
          FUTEX_BITSET_MATCH_ANY);
}

}  // namespace rigid::loop
