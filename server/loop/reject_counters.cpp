#include "loop/reject_counters.hpp"

#include <algorithm>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <string>

namespace rigid::loop {

char* RejectCounters::count_and_claim(RejectReason reason) {
  Slot& s = slots_[index(reason)];
  s.count.fetch_add(1, std::memory_order_relaxed);
  if (s.first.load(std::memory_order_relaxed) != kNone) return nullptr;
  int expected = kNone;
  return s.first.compare_exchange_strong(expected, kWriting, std::memory_order_acquire) ? s.detail
                                                                                        : nullptr;
}

void RejectCounters::record(RejectReason reason, std::string_view detail) {
  if (char* buffer = count_and_claim(reason)) {
    const std::size_t n = std::min(detail.size(), kDetailSize - 1);
    std::memcpy(buffer, detail.data(), n);
    buffer[n] = '\0';
    publish(reason);
  }
}

void RejectCounters::recordf(RejectReason reason, const char* format, ...) {
  if (char* buffer = count_and_claim(reason)) {
    va_list args;
    va_start(args, format);
    std::vsnprintf(buffer, kDetailSize, format, args);
    va_end(args);
    publish(reason);
  }
}

std::int64_t RejectCounters::total() const {
  std::int64_t sum = 0;
  for (const Slot& s : slots_)
    sum += s.count.load(std::memory_order_relaxed);
  return sum;
}

transport::RejectCounts RejectCounters::counts() const {
  transport::RejectCounts c;
  c.non_finite = count(RejectReason::kNonFinite);
  c.unknown_body = count(RejectReason::kUnknownBody);
  c.over_limit = count(RejectReason::kOverLimit);
  c.undecodable = count(RejectReason::kUndecodable);
  c.stale_sequence = count(RejectReason::kStaleSequence);
  c.queue_full = count(RejectReason::kQueueFull);
  c.invalid = count(RejectReason::kInvalid);
  return c;
}

void RejectCounters::flush(Log& log) {
  for (std::size_t i = 0; i < slots_.size(); ++i) {
    Slot& s = slots_[i];
    if (s.first.load(std::memory_order_acquire) != kReady) continue;
    log.line("rejected " + std::string(to_string(static_cast<RejectReason>(i))) + ": " + s.detail +
             " (the first of its kind; Stats counts the others)");
    s.first.store(kLogged, std::memory_order_relaxed);
  }
}

}  // namespace rigid::loop
