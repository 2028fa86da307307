#include "loop/sender_rates.hpp"

#include <algorithm>

namespace rigid::loop {

bool SenderRates::take(std::uint64_t sender, std::int64_t now_ns) {
  Bucket* b = buckets_.find(sender);
  if (b == nullptr) {
    if (buckets_.full()) evict_least_recent();
    buckets_.put(sender, Bucket{burst_, now_ns});
    b = buckets_.find(sender);
  }
  b->tokens = std::min(burst_, b->tokens + static_cast<double>(now_ns - b->last_ns) * rate_per_ns_);
  b->last_ns = now_ns;
  if (b->tokens < 1.0) return false;
  b->tokens -= 1.0;
  return true;
}

void SenderRates::evict_least_recent() {
  std::uint64_t oldest = 0;
  std::int64_t oldest_ns = INT64_MAX;
  buckets_.for_each([&](std::uint64_t key, const Bucket& b) {
    if (b.last_ns < oldest_ns) {
      oldest_ns = b.last_ns;
      oldest = key;
    }
  });
  buckets_.erase(oldest);
}

}  // namespace rigid::loop
