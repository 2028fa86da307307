// A fixed-size histogram of non-negative durations in nanoseconds, for percentiles without storing
// samples and without allocating after construction (the loop thread records into it every tick).
//
// Buckets are log-linear: values below 128 ns are exact; above, each power of two is split into 64
// buckets, so a percentile is within 1/64 (1.6%) of the true sample value, from 128 ns to 10^12 ns
// (larger values land in the last bucket). The maximum is kept exactly.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

namespace rigid::loop {

class Histogram {
 public:
  static constexpr int kExactBelow = 128;
  static constexpr int kSubBuckets = 64;  // per power of two above kExactBelow
  static constexpr int kOctaves = 34;     // 2^7 .. 2^41 ns (~37 minutes)
  static constexpr int kBuckets = kExactBelow + kOctaves * kSubBuckets;

  void record(std::int64_t ns);
  void clear();
  // Adds another histogram's samples.
  void merge(const Histogram& other);

  std::int64_t count() const { return count_; }
  // The samples in one bucket (0 <= bucket < kBuckets), for writing the whole distribution out.
  std::int64_t count_in(int bucket) const { return counts_[static_cast<std::size_t>(bucket)]; }
  std::int64_t max() const { return max_; }
  // The smallest value v such that at least a fraction q of the samples are <= v, reported as the
  // midpoint of its bucket (exact below kExactBelow, and never above max()). 0 when empty.
  // q in [0, 1].
  std::int64_t percentile(double q) const;

  static int bucket_of(std::int64_t ns);
  static std::int64_t bucket_low(int bucket);
  static std::int64_t bucket_high(int bucket);  // inclusive

 private:
  std::array<std::int64_t, kBuckets> counts_{};
  std::int64_t count_ = 0;
  std::int64_t max_ = 0;
};

}  // namespace rigid::loop
