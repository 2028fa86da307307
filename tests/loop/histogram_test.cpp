// Percentiles from the fixed histogram, and the one-second windows of TickStats.
#include "loop/histogram.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "loop/tick_stats.hpp"

namespace rigid::loop {
namespace {

TEST(Histogram, SmallValuesAreExact) {
  Histogram h;
  for (int v = 1; v <= 100; ++v)
    h.record(v);
  EXPECT_EQ(h.count(), 100);
  EXPECT_EQ(h.percentile(0.5), 50);
  EXPECT_EQ(h.percentile(0.99), 99);
  EXPECT_EQ(h.percentile(1.0), 100);
  EXPECT_EQ(h.percentile(0.0), 1);
  EXPECT_EQ(h.max(), 100);
}

TEST(Histogram, BucketCountsHoldEverySampleWhereItFalls) {
  Histogram h;
  const std::int64_t samples[] = {3, 3, 500, 70'000, 70'500, 9'000'000};
  for (std::int64_t v : samples)
    h.record(v);
  std::int64_t total = 0;
  for (int b = 0; b < Histogram::kBuckets; ++b)
    total += h.count_in(b);
  EXPECT_EQ(total, h.count());
  EXPECT_EQ(h.count_in(Histogram::bucket_of(3)), 2);
  EXPECT_EQ(h.count_in(Histogram::bucket_of(500)), 1);
  EXPECT_EQ(h.count_in(Histogram::bucket_of(9'000'000)), 1);
  // 70 000 and 70 500 ns are 0.7% apart: the same bucket or neighbours, never lost.
  EXPECT_EQ(h.count_in(Histogram::bucket_of(70'000)) +
                (Histogram::bucket_of(70'500) != Histogram::bucket_of(70'000)
                     ? h.count_in(Histogram::bucket_of(70'500))
                     : 0),
            2);
}

TEST(Histogram, LargeValuesAreWithinTheBucketPrecision) {
  // 1..100000 us in ns, uniform: p50 = 50 ms, p99 = 99 ms, within 1/64.
  Histogram h;
  for (int us = 1; us <= 100000; ++us)
    h.record(std::int64_t{us} * 1000);
  EXPECT_NEAR(static_cast<double>(h.percentile(0.5)), 50e6, 50e6 / 64);
  EXPECT_NEAR(static_cast<double>(h.percentile(0.99)), 99e6, 99e6 / 64);
  EXPECT_EQ(h.max(), 100'000'000);
  EXPECT_LE(h.percentile(1.0), h.max());
}

TEST(Histogram, BucketsTileTheRange) {
  for (int b = 0; b + 1 < Histogram::kBuckets; ++b) {
    ASSERT_EQ(Histogram::bucket_high(b) + 1, Histogram::bucket_low(b + 1)) << b;
    ASSERT_EQ(Histogram::bucket_of(Histogram::bucket_low(b)), b);
    ASSERT_EQ(Histogram::bucket_of(Histogram::bucket_high(b)), b);
  }
  EXPECT_EQ(Histogram::bucket_of(-5), 0);
  EXPECT_EQ(Histogram::bucket_of(INT64_MAX), Histogram::kBuckets - 1);
}

TEST(Histogram, OutliersShowInTheTailOnly) {
  Histogram h;
  for (int i = 0; i < 990; ++i)
    h.record(20'000);  // 20 us
  for (int i = 0; i < 10; ++i)
    h.record(500'000);  // 500 us
  EXPECT_NEAR(static_cast<double>(h.percentile(0.5)), 20e3, 20e3 / 64);
  EXPECT_NEAR(static_cast<double>(h.percentile(0.99)), 20e3, 20e3 / 64);
  EXPECT_NEAR(static_cast<double>(h.percentile(0.995)), 500e3, 500e3 / 64);
  EXPECT_EQ(h.max(), 500'000);
}

TEST(Histogram, EmptyIsZeroAndMergeAdds) {
  Histogram a, b;
  EXPECT_EQ(a.percentile(0.99), 0);
  a.record(10);
  b.record(30);
  b.record(40);
  a.merge(b);
  EXPECT_EQ(a.count(), 3);
  EXPECT_EQ(a.percentile(0.5), 30);
  EXPECT_EQ(a.max(), 40);
  a.clear();
  EXPECT_EQ(a.count(), 0);
  EXPECT_EQ(a.max(), 0);
}

TEST(TickStats, WindowsReportTheirOwnFiguresAndTotalsEverything) {
  TickStats s(1e-3, 0, 1'000'000'000);
  for (int i = 0; i < 1000; ++i) {
    s.count_tick();
    s.record_lateness(10'000);
    s.record_step_cost(50'000);
  }
  s.add_overruns(2);
  EXPECT_FALSE(s.window_due(999'999'999));
  EXPECT_TRUE(s.window_due(1'000'000'000));
  const LoopSummary w1 = s.close_window(1'000'000'000, 1000, 1.0, rigid::Mode::kRealtime, false);
  EXPECT_NEAR(w1.rtf_last_second, 1.0, 1e-12);
  EXPECT_NEAR(w1.lateness_p99_us, 10.0, 10.0 / 64);
  EXPECT_NEAR(w1.step_cost_p50_us, 50.0, 50.0 / 64);
  EXPECT_EQ(w1.overruns, 2);
  // A second window at half speed with worse lateness: its own figures, totals over both.
  for (int i = 0; i < 500; ++i) {
    s.count_tick();
    s.record_lateness(90'000);
  }
  const LoopSummary w2 = s.close_window(2'000'000'000, 1500, 1.5, rigid::Mode::kRealtime, false);
  EXPECT_NEAR(w2.rtf_last_second, 0.5, 1e-12);
  EXPECT_NEAR(w2.rtf_since_start, 0.75, 1e-12);
  EXPECT_NEAR(w2.lateness_p50_us, 90.0, 90.0 / 64);
  EXPECT_EQ(w2.overruns, 2);
  const RunTotals t = s.totals(2'000'000'000);
  EXPECT_EQ(t.ticks_stepped, 1500);
  EXPECT_EQ(t.lateness.count(), 1500);
  EXPECT_NEAR(static_cast<double>(t.lateness.percentile(0.5)), 10e3, 10e3 / 64);
  EXPECT_NEAR(static_cast<double>(t.lateness.percentile(0.99)), 90e3, 90e3 / 64);
  EXPECT_NEAR(t.sim_s_stepped, 1.5, 1e-12);
}

}  // namespace
}  // namespace rigid::loop
