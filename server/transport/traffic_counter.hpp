// A transport's running totals, updated from its publishing and receiving threads and read by
// whoever builds Stats. Relaxed atomics: the figures are independent counts, not a snapshot.
#pragma once

#include <atomic>
#include <cstdint>

#include "rigid/messages.hpp"
#include "transport/transport.hpp"

namespace rigid::transport {

class TrafficCounter {
 public:
  PublishResult count(PublishResult result) {
    if (result == PublishResult::kOk) {
      sent_.fetch_add(1, std::memory_order_relaxed);
    } else if (result == PublishResult::kFailed) {
      send_failures_.fetch_add(1, std::memory_order_relaxed);
    }
    return result;
  }
  void received() { received_.fetch_add(1, std::memory_order_relaxed); }
  void decode_failed() { decode_failures_.fetch_add(1, std::memory_order_relaxed); }

  TransportCounts snapshot() const {
    return {sent_.load(std::memory_order_relaxed), send_failures_.load(std::memory_order_relaxed),
            received_.load(std::memory_order_relaxed),
            decode_failures_.load(std::memory_order_relaxed)};
  }

 private:
  std::atomic<std::int64_t> sent_{0};
  std::atomic<std::int64_t> send_failures_{0};
  std::atomic<std::int64_t> received_{0};
  std::atomic<std::int64_t> decode_failures_{0};
};

}  // namespace rigid::transport
