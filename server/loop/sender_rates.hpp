// Each sender's share of the command rate: a token bucket per sender (Sender::key), refilled at
// `rate` commands per second up to `burst`. One per intake (one transport thread: no locking).
// Fixed capacity; when full, the sender heard from least recently is forgotten (it comes back
// with a full bucket, which costs it nothing it could not have had by waiting).
#pragma once

#include <cstdint>

#include "util/fixed_map.hpp"

namespace rigid::loop {

class SenderRates {
 public:
  SenderRates(double rate_per_s, double burst, std::size_t capacity)
      : rate_per_ns_(rate_per_s * 1e-9), burst_(burst), buckets_(capacity) {}

  // true: the sender may send one more command now (a token is taken).
  bool take(std::uint64_t sender, std::int64_t now_ns);

 private:
  struct Bucket {
    double tokens = 0.0;
    std::int64_t last_ns = 0;
  };
  struct Hash {
    std::uint64_t operator()(std::uint64_t key) const { return util::mix64(key); }
  };
  void evict_least_recent();

  double rate_per_ns_;
  double burst_;
  util::FixedMap<std::uint64_t, Bucket, Hash> buckets_;
};

}  // namespace rigid::loop
