#include "loop/fixed_rate_schedule.hpp"

#include <cmath>

namespace rigid::loop {

FixedRateSchedule::FixedRateSchedule(std::int64_t origin_ns, double period_ns)
    : origin_ns_(origin_ns), period_ns_(period_ns) {}

std::int64_t FixedRateSchedule::deadline_of(std::int64_t slot) const {
  // long double (64-bit mantissa on x86-64): exact to the nanosecond for centuries of slots.
  const long double offset = static_cast<long double>(slot) * period_ns_;
  return origin_ns_ + static_cast<std::int64_t>(std::llroundl(offset));
}

std::int64_t FixedRateSchedule::advance(std::int64_t now_ns) {
  const std::int64_t next = slot_ + 1;
  if (now_ns <= deadline_of(next)) {
    slot_ = next;
    return 0;
  }
  // The first slot due at or after now_ns: estimated by division, then corrected for rounding.
  auto first = static_cast<std::int64_t>(
      std::floor(static_cast<long double>(now_ns - origin_ns_) / period_ns_));
  if (first < next) first = next;
  while (deadline_of(first) < now_ns)
    ++first;
  while (first > next && deadline_of(first - 1) >= now_ns)
    --first;
  const std::int64_t skipped = first - next;
  slot_ = first;
  return skipped;
}

void FixedRateSchedule::restart(std::int64_t origin_ns, double period_ns) {
  origin_ns_ = origin_ns;
  period_ns_ = period_ns;
  slot_ = 0;
}

}  // namespace rigid::loop
