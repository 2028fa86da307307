#include "loop/histogram.hpp"

#include <algorithm>
#include <bit>
#include <cmath>

namespace rigid::loop {

int Histogram::bucket_of(std::int64_t ns) {
  if (ns < kExactBelow) return ns < 0 ? 0 : static_cast<int>(ns);
  const auto v = static_cast<std::uint64_t>(ns);
  const int exponent = std::bit_width(v) - 1;  // >= 7
  const int octave = exponent - 7;
  if (octave >= kOctaves) return kBuckets - 1;
  const auto sub = static_cast<int>((v >> (exponent - 6)) & (kSubBuckets - 1));
  return kExactBelow + octave * kSubBuckets + sub;
}

std::int64_t Histogram::bucket_low(int bucket) {
  if (bucket < kExactBelow) return bucket;
  const int octave = (bucket - kExactBelow) / kSubBuckets;
  const int sub = (bucket - kExactBelow) % kSubBuckets;
  const int exponent = octave + 7;
  return (std::int64_t{1} << exponent) + (static_cast<std::int64_t>(sub) << (exponent - 6));
}

std::int64_t Histogram::bucket_high(int bucket) {
  if (bucket < kExactBelow) return bucket;
  if (bucket == kBuckets - 1) return INT64_MAX;
  return bucket_low(bucket + 1) - 1;
}

void Histogram::record(std::int64_t ns) {
  if (ns < 0) ns = 0;
  ++counts_[static_cast<std::size_t>(bucket_of(ns))];
  ++count_;
  max_ = std::max(max_, ns);
}

void Histogram::clear() {
  counts_.fill(0);
  count_ = 0;
  max_ = 0;
}

void Histogram::merge(const Histogram& other) {
  for (std::size_t i = 0; i < counts_.size(); ++i)
    counts_[i] += other.counts_[i];
  count_ += other.count_;
  max_ = std::max(max_, other.max_);
}

std::int64_t Histogram::percentile(double q) const {
  if (count_ == 0) return 0;
  q = std::clamp(q, 0.0, 1.0);
  // Rank of the sample wanted, 1-based: at least a fraction q of the samples at or below it.
  const auto rank = std::max<std::int64_t>(
      1, static_cast<std::int64_t>(std::ceil(q * static_cast<double>(count_))));
  std::int64_t seen = 0;
  for (int b = 0; b < kBuckets; ++b) {
    seen += counts_[static_cast<std::size_t>(b)];
    if (seen >= rank) {
      if (b < kExactBelow) return b;
      const std::int64_t high = std::min(bucket_high(b), max_);
      const std::int64_t low = std::min(bucket_low(b), high);
      return low + (high - low) / 2;
    }
  }
  return max_;
}

}  // namespace rigid::loop
