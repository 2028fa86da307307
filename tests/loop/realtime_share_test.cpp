// RealtimeShare: a thread that takes more than its limit of a CPU over a window steps down, and
// steps back up only below the lower resume share; windows shorter than the window length, and
// clocks that go backwards, decide nothing.
#include "loop/realtime_share.hpp"

#include <gtest/gtest.h>

namespace rigid::loop {
namespace {

using Change = RealtimeShare::Change;
constexpr std::int64_t kSecond = 1'000'000'000;

TEST(RealtimeShare, StepsDownAboveTheLimitAndUpOnlyBelowTheResumeShare) {
  RealtimeShare s(0.25, 0.10, kSecond);
  std::int64_t cpu = 5 * kSecond, wall = 100 * kSecond;
  EXPECT_EQ(s.update(cpu, wall), Change::kNone);  // starts the first window
  // A window at 24%: stays.
  cpu += kSecond * 24 / 100;
  wall += kSecond;
  EXPECT_EQ(s.update(cpu, wall), Change::kNone);
  EXPECT_NEAR(s.last_share(), 0.24, 1e-12);
  EXPECT_FALSE(s.stepped_down());
  // 30%, measured over 2 s: down, once.
  cpu += 2 * kSecond * 30 / 100;
  wall += 2 * kSecond;
  EXPECT_EQ(s.update(cpu, wall), Change::kStepDown);
  EXPECT_TRUE(s.stepped_down());
  EXPECT_NEAR(s.last_share(), 0.30, 1e-12);
  cpu += kSecond * 90 / 100;
  wall += kSecond;
  EXPECT_EQ(s.update(cpu, wall), Change::kNone);  // still above: already down
  // Between the two shares: stays down (no flapping around one threshold).
  cpu += kSecond * 15 / 100;
  wall += kSecond;
  EXPECT_EQ(s.update(cpu, wall), Change::kNone);
  EXPECT_TRUE(s.stepped_down());
  // Below the resume share: back up.
  cpu += kSecond * 5 / 100;
  wall += kSecond;
  EXPECT_EQ(s.update(cpu, wall), Change::kStepUp);
  EXPECT_FALSE(s.stepped_down());
}

TEST(RealtimeShare, AShortWindowDecidesNothingAndItsTimeCountsInTheNext) {
  RealtimeShare s(0.25, 0.10, kSecond);
  EXPECT_EQ(s.update(0, 0), Change::kNone);
  // 0.9 s, all of it on the CPU: not a whole window yet.
  EXPECT_EQ(s.update(kSecond * 9 / 10, kSecond * 9 / 10), Change::kNone);
  EXPECT_FALSE(s.stepped_down());
  // The window closes at 1 s, counting the 0.9 s: 0.9 s of CPU over 1 s.
  EXPECT_EQ(s.update(kSecond * 9 / 10, kSecond), Change::kStepDown);
  EXPECT_NEAR(s.last_share(), 0.9, 1e-12);
}

TEST(RealtimeShare, ClocksGoingBackwardsStartANewWindow) {
  RealtimeShare s(0.25, 0.10, kSecond);
  EXPECT_EQ(s.update(10 * kSecond, 50 * kSecond), Change::kNone);
  // The thread's CPU clock behind its start (not a clock of this thread): no share from it.
  EXPECT_EQ(s.update(kSecond, 52 * kSecond), Change::kNone);
  EXPECT_EQ(s.last_share(), 0.0);
  // The new window starts there: 0.5 s of CPU in the next 2 s is 25%, not above the limit.
  EXPECT_EQ(s.update(kSecond + kSecond / 2, 54 * kSecond), Change::kNone);
  EXPECT_NEAR(s.last_share(), 0.25, 1e-12);
  // Wall time going backwards: likewise.
  EXPECT_EQ(s.update(3 * kSecond, 10 * kSecond), Change::kNone);
  EXPECT_FALSE(s.stepped_down());
}

}  // namespace
}  // namespace rigid::loop
