#include "loop/reject_counters.hpp"

#include <algorithm>
#include <climits>
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

RejectCounters::SenderSlot* RejectCounters::find_or_claim(const Sender& sender) {
  SenderSlot* least = nullptr;
  for (SenderSlot& slot : senders_) {
    if (!slot.used) {
      slot = SenderSlot{};
      slot.sender = sender;
      slot.used = true;
      return &slot;
    }
    if (slot.sender.key == sender.key) return &slot;
    if (least == nullptr || slot.count < least->count) least = &slot;
  }
  *least = SenderSlot{};
  least->sender = sender;
  least->used = true;
  return least;
}

void RejectCounters::note(RejectReason reason, const Sender* sender, std::string_view detail) {
  const std::lock_guard lock(mutex_);
  const std::size_t n = std::min(detail.size(), kDetailSize - 1);
  std::memcpy(last_detail_, detail.data(), n);
  last_detail_[n] = '\0';
  if (sender == nullptr) return;
  SenderSlot* slot = find_or_claim(*sender);
  ++slot->count;
  slot->last = reason;
}

void RejectCounters::record(RejectReason reason, std::string_view detail, const Sender* sender) {
  if (char* buffer = count_and_claim(reason)) {
    const std::size_t n = std::min(detail.size(), kDetailSize - 1);
    std::memcpy(buffer, detail.data(), n);
    buffer[n] = '\0';
    publish(reason);
  }
  note(reason, sender, detail);
}

void RejectCounters::recordf(RejectReason reason, const Sender* sender, const char* format, ...) {
  char line[kDetailSize];
  va_list args;
  va_start(args, format);
  std::vsnprintf(line, sizeof line, format, args);
  va_end(args);
  record(reason, line, sender);
}

bool RejectCounters::reply_allowed(const Sender& sender, std::int64_t now_ns) {
  const std::lock_guard lock(mutex_);
  SenderSlot* slot = find_or_claim(sender);
  if (now_ns - slot->reply_window_ns >= 1'000'000'000) {
    slot->reply_window_ns = now_ns;
    slot->replies = 0;
  }
  if (slot->replies >= kRepliesPerSecond) return false;
  ++slot->replies;
  return true;
}

std::int64_t RejectCounters::total() const {
  std::int64_t sum = 0;
  for (const Slot& s : slots_)
    sum += s.count.load(std::memory_order_relaxed);
  return sum;
}

rigid::RejectCounts RejectCounters::counts() const {
  rigid::RejectCounts c;
  c.non_finite = count(RejectReason::kNonFinite);
  c.unknown_body = count(RejectReason::kUnknownBody);
  c.over_limit = count(RejectReason::kOverLimit);
  c.undecodable = count(RejectReason::kUndecodable);
  c.stale_sequence = count(RejectReason::kStaleSequence);
  c.queue_full = count(RejectReason::kQueueFull);
  c.invalid = count(RejectReason::kInvalid);
  c.over_share = count(RejectReason::kOverShare);
  c.rate_limited = count(RejectReason::kRateLimited);
  c.not_permitted = count(RejectReason::kNotPermitted);
  return c;
}

std::vector<rigid::SourceRefusals> RejectCounters::top_senders() const {
  std::vector<const SenderSlot*> used;
  const std::lock_guard lock(mutex_);
  for (const SenderSlot& slot : senders_)
    if (slot.used && slot.count > 0) used.push_back(&slot);
  const std::size_t n = std::min(used.size(), rigid::kMaxRefusedSources);
  std::partial_sort(used.begin(), used.begin() + static_cast<std::ptrdiff_t>(n), used.end(),
                    [](const SenderSlot* a, const SenderSlot* b) { return a->count > b->count; });
  std::vector<rigid::SourceRefusals> top(n);
  for (std::size_t i = 0; i < n; ++i) {
    top[i].sender = used[i]->sender.name;
    top[i].count = used[i]->count;
    top[i].last_reason = std::string(to_string(used[i]->last));
  }
  return top;
}

void RejectCounters::flush(Log& log, std::int64_t now_ns) {
  for (std::size_t i = 0; i < slots_.size(); ++i) {
    Slot& s = slots_[i];
    if (s.first.load(std::memory_order_acquire) != kReady) continue;
    log.line("rejected " + std::string(to_string(static_cast<RejectReason>(i))) + ": " + s.detail +
             " (the first of its kind; Stats counts the others)");
    s.first.store(kLogged, std::memory_order_relaxed);
    // The first one is told in full: the summary counts from after it.
    logged_counts_[i] += 1;
  }
  if (now_ns < next_summary_ns_) return;
  next_summary_ns_ = now_ns > INT64_MAX - 1'000'000'000 ? INT64_MAX : now_ns + 1'000'000'000;
  std::string by_reason;
  std::int64_t refused = 0;
  for (std::size_t i = 0; i < slots_.size(); ++i) {
    const std::int64_t c = slots_[i].count.load(std::memory_order_relaxed);
    const std::int64_t fresh = c - std::min(c, logged_counts_[i]);
    logged_counts_[i] = std::max(c, logged_counts_[i]);
    if (fresh == 0) continue;
    refused += fresh;
    by_reason += (by_reason.empty() ? "" : ", ") +
                 std::string(to_string(static_cast<RejectReason>(i))) + " " + std::to_string(fresh);
  }
  if (refused == 0) return;
  const std::lock_guard lock(mutex_);
  const SenderSlot* busiest = nullptr;
  for (SenderSlot& slot : senders_) {
    if (!slot.used) continue;
    if (busiest == nullptr ||
        slot.count - slot.count_logged > busiest->count - busiest->count_logged) {
      busiest = &slot;
    }
  }
  std::string line = "refused " + std::to_string(refused) + " command(s) since the last report (" +
                     by_reason + ")";
  if (busiest != nullptr && busiest->count > busiest->count_logged) {
    line += "; most from " + std::string(busiest->sender.name) + " (" +
            std::to_string(busiest->count - busiest->count_logged) + ")";
  }
  for (SenderSlot& slot : senders_)
    slot.count_logged = slot.count;
  line += "; last: " + std::string(last_detail_);
  log.line(line);
}

}  // namespace rigid::loop
