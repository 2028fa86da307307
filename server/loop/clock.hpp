// The two clocks the loop uses. Deadlines and durations are on CLOCK_MONOTONIC (never jumps);
// wall-clock stamps on messages are CLOCK_REALTIME (comparable across processes and hosts).
// Both in integer nanoseconds.
#pragma once

#include <cstdint>

namespace rigid::loop {

std::int64_t monotonic_ns();
std::int64_t realtime_ns();

// Sleeps until CLOCK_MONOTONIC reaches `deadline_ns` (clock_nanosleep with TIMER_ABSTIME, so a
// late wake-up never shifts later deadlines). Returns early, with false, only when interrupted by
// a signal; a deadline in the past returns at once.
bool sleep_until(std::int64_t deadline_ns);

}  // namespace rigid::loop
