// Refused commands, counted by reason (Stats.rejected), and the first refusal of each reason kept
// for the log. Any thread may record (the transport threads for what they validate, the loop
// thread for stale sequence numbers and a full wrench table); recording allocates nothing and
// never blocks. The housekeeping thread writes the kept lines to the log (flush), so the loop
// thread never does I/O.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <string_view>

#include "loop/command.hpp"
#include "loop/log.hpp"
#include "transport/messages.hpp"

namespace rigid::loop {

class RejectCounters {
 public:
  // Counts one refusal; if it is the first of its reason, keeps `detail` (truncated to a line).
  void record(RejectReason reason, std::string_view detail);
  // The same, with the detail formatted printf-style into a fixed buffer (no allocation; for the
  // loop thread).
  void recordf(RejectReason reason, const char* format, ...) __attribute__((format(printf, 3, 4)));

  std::int64_t count(RejectReason reason) const {
    return slots_[index(reason)].count.load(std::memory_order_relaxed);
  }
  std::int64_t total() const;
  transport::RejectCounts counts() const;

  // Logs each first refusal not logged yet: "rejected REASON: DETAIL (...)".
  void flush(Log& log);

 private:
  static constexpr std::size_t kDetailSize = 240;
  enum : int { kNone = 0, kWriting = 1, kReady = 2, kLogged = 3 };
  struct Slot {
    std::atomic<std::int64_t> count{0};
    std::atomic<int> first{kNone};
    char detail[kDetailSize] = {};
  };
  static std::size_t index(RejectReason r) { return static_cast<std::size_t>(r); }
  // Counts, and returns the slot's buffer if this call is the first of its reason (else null);
  // the caller fills it and calls publish.
  char* count_and_claim(RejectReason reason);
  void publish(RejectReason reason) {
    slots_[index(reason)].first.store(kReady, std::memory_order_release);
  }

  std::array<Slot, kRejectReasonCount> slots_;
};

}  // namespace rigid::loop
