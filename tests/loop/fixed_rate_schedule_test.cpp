// The scheduler's arithmetic: deadlines from the origin (no drift), and the overrun policy (count
// and skip to the first deadline still ahead).
#include "loop/fixed_rate_schedule.hpp"

#include <gtest/gtest.h>

namespace rigid::loop {
namespace {

TEST(FixedRateSchedule, DeadlinesAreOriginPlusSlotTimesPeriod) {
  const FixedRateSchedule s(5'000, 1e6);
  EXPECT_EQ(s.deadline(), 5'000);
  EXPECT_EQ(s.deadline_of(1), 1'005'000);
  EXPECT_EQ(s.deadline_of(1'000'000), 1'000'000'005'000);
}

TEST(FixedRateSchedule, FractionalPeriodsDoNotDrift) {
  // 1/3 ms: adding a rounded period each tick would drift by 1/3 ns per tick.
  const FixedRateSchedule s(0, 1e6 / 3.0);
  EXPECT_EQ(s.deadline_of(3), 1'000'000);
  EXPECT_EQ(s.deadline_of(3'000'000'000LL), 1'000'000'000'000'000LL);
  EXPECT_EQ(s.deadline_of(1), 333'333);
  EXPECT_EQ(s.deadline_of(2), 666'667);
}

TEST(FixedRateSchedule, OnTimeTicksAdvanceOneSlot) {
  FixedRateSchedule s(0, 1000);
  EXPECT_EQ(s.advance(400), 0);
  EXPECT_EQ(s.slot(), 1);
  EXPECT_EQ(s.deadline(), 1000);
  // Ending exactly at the next deadline is on time.
  EXPECT_EQ(s.advance(2000), 0);
  EXPECT_EQ(s.deadline(), 2000);
}

TEST(FixedRateSchedule, OverrunsSkipToTheFirstDeadlineAhead) {
  FixedRateSchedule s(0, 1000);
  // Slot 0's tick ends at 1001: slot 1 (due 1000) is missed; slot 2 (due 2000) is next.
  EXPECT_EQ(s.advance(1001), 1);
  EXPECT_EQ(s.slot(), 2);
  EXPECT_EQ(s.deadline(), 2000);
  // Slot 2's tick ends at 5500: slots 3, 4, 5 are missed; slot 6 (6000) is next.
  EXPECT_EQ(s.advance(5500), 3);
  EXPECT_EQ(s.deadline(), 6000);
  // Ending exactly at a later deadline: that slot still runs (its deadline has not passed).
  EXPECT_EQ(s.advance(8000), 1);
  EXPECT_EQ(s.deadline(), 8000);
}

TEST(FixedRateSchedule, OverrunArithmeticHoldsWithRoundedDeadlines) {
  FixedRateSchedule s(7, 1e6 / 3.0);
  for (std::int64_t now : {1'000'000LL, 1'000'008LL, 123'456'789LL, 999'999'999'999LL}) {
    const std::int64_t before = s.slot();
    const std::int64_t skipped = s.advance(now);
    EXPECT_GE(s.deadline(), now);
    EXPECT_LT(s.deadline_of(s.slot() - 1), now);
    EXPECT_EQ(skipped, s.slot() - before - 1);
  }
}

TEST(FixedRateSchedule, RestartSetsANewOriginAndPeriod) {
  FixedRateSchedule s(0, 1000);
  s.advance(500);
  s.restart(10'000, 500);  // e.g. real-time factor 2
  EXPECT_EQ(s.slot(), 0);
  EXPECT_EQ(s.deadline(), 10'000);
  EXPECT_EQ(s.advance(10'100), 0);
  EXPECT_EQ(s.deadline(), 10'500);
}

}  // namespace
}  // namespace rigid::loop
