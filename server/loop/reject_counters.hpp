// Refused commands: counted by reason (Stats.rejected) and by sender (Stats.refused_by_source),
// logged so that the log stays readable under attack, and answered at a bounded rate.
//
// Any thread may record (the transport threads for what they validate, the loop thread for stale
// sequence numbers and a full share of the wrench table); recording allocates nothing. The
// housekeeping thread writes the log (flush), so the loop thread never does I/O:
// - the first refusal of each reason is logged at once with its detail ("rejected REASON: ...");
// - after it, refusals are aggregated: at most one line per second, with the counts by reason,
//   the sender refused most in that second and the last detail.
// The per-sender table holds kSenderSlots senders; past that, the sender refused least is
// replaced (an attacker cycling sessions cannot hide its refusals from the busiest senders).
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <mutex>
#include <string_view>
#include <vector>

#include "loop/command.hpp"
#include "loop/log.hpp"
#include "rigid/messages.hpp"

namespace rigid::loop {

class RejectCounters {
 public:
  // Counts one refusal; if it is the first of its reason, keeps `detail` (truncated to a line).
  // `sender` may be null (an undecodable payload has none).
  void record(RejectReason reason, std::string_view detail, const Sender* sender = nullptr);
  // The same, with the detail formatted printf-style into a fixed buffer (no allocation; for the
  // loop thread).
  void recordf(RejectReason reason, const Sender* sender, const char* format, ...)
      __attribute__((format(printf, 4, 5)));

  // Whether a refused wrench from `sender` may be answered now: at most kRepliesPerSecond per
  // sender, so that refusals cannot be turned into a flood of replies.
  bool reply_allowed(const Sender& sender, std::int64_t now_ns);

  std::int64_t count(RejectReason reason) const {
    return slots_[index(reason)].count.load(std::memory_order_relaxed);
  }
  std::int64_t total() const;
  rigid::RejectCounts counts() const;
  // The senders refused most since start, most first, at most rigid::kMaxRefusedSources.
  std::vector<rigid::SourceRefusals> top_senders() const;

  // Logs the first refusals not logged yet, and, at most once per second, one line summing up the
  // refusals since the last such line. `now_ns` is CLOCK_MONOTONIC.
  void flush(Log& log, std::int64_t now_ns);

  static constexpr int kRepliesPerSecond = 5;
  static constexpr std::size_t kSenderSlots = 256;

 private:
  static constexpr std::size_t kDetailSize = 240;
  enum : int { kNone = 0, kWriting = 1, kReady = 2, kLogged = 3 };
  struct Slot {
    std::atomic<std::int64_t> count{0};
    std::atomic<int> first{kNone};
    char detail[kDetailSize] = {};
  };
  struct SenderSlot {
    Sender sender;
    std::int64_t count = 0;
    std::int64_t count_logged = 0;  // count at the last summary line
    RejectReason last = RejectReason::kInvalid;
    std::int64_t reply_window_ns = 0;  // start of the current one-second reply window
    int replies = 0;                   // in that window
    bool used = false;
  };
  static std::size_t index(RejectReason r) { return static_cast<std::size_t>(r); }
  // Counts, and returns the slot's buffer if this call is the first of its reason (else null);
  // the caller fills it and calls publish.
  char* count_and_claim(RejectReason reason);
  void publish(RejectReason reason) {
    slots_[index(reason)].first.store(kReady, std::memory_order_release);
  }
  void note(RejectReason reason, const Sender* sender, std::string_view detail);
  SenderSlot* find_or_claim(const Sender& sender);  // mutex_ held

  std::array<Slot, kRejectReasonCount> slots_;

  mutable std::mutex mutex_;  // guards everything below
  std::array<SenderSlot, kSenderSlots> senders_{};
  std::array<std::int64_t, kRejectReasonCount> logged_counts_{};  // at the last summary line
  char last_detail_[kDetailSize] = {};
  std::int64_t next_summary_ns_ = 0;
};

}  // namespace rigid::loop
