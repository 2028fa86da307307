#include "loop/clock.hpp"

#include <time.h>

#include <cerrno>

namespace rigid::loop {
namespace {

constexpr std::int64_t kNsPerSecond = 1'000'000'000;

std::int64_t now(clockid_t clock) {
  timespec ts{};
  clock_gettime(clock, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * kNsPerSecond + ts.tv_nsec;
}

}  // namespace

std::int64_t monotonic_ns() {
  return now(CLOCK_MONOTONIC);
}

std::int64_t realtime_ns() {
  return now(CLOCK_REALTIME);
}

bool sleep_until(std::int64_t deadline_ns) {
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(deadline_ns / kNsPerSecond);
  ts.tv_nsec = static_cast<long>(deadline_ns % kNsPerSecond);
  // clock_nanosleep returns the error number rather than setting errno.
  return clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) != EINTR;
}

}  // namespace rigid::loop
