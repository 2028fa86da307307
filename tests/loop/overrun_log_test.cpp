// What rigidd logs about skipped ticks on a host that stays busy: the first overrun at once, then
// at most one line per interval summing up the ticks skipped since the last line, each with what
// to do about it; nothing while no tick is skipped.
#include "loop/overrun_log.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace rigid::loop {
namespace {

constexpr std::int64_t kMs = 1'000'000;

TEST(OverrunLog, OneLinePerIntervalAtMostWithTheCountAndAHint) {
  OverrunLog log;
  std::vector<std::string> lines;
  std::vector<std::int64_t> at_ms;
  // 60 s of a host on which the loop skips 3 ticks every 100 ms, as housekeeping polls.
  std::int64_t overruns = 0;
  for (std::int64_t t = 0; t <= 60'000; t += 100) {
    overruns += 3;
    if (auto line = log.update(overruns, 1'000 * kMs + t * kMs)) {
      lines.push_back(*line);
      at_ms.push_back(t);
    }
  }
  // The first at once, then one per 10 s: at 0, 10, 20, ..., 60 s.
  ASSERT_EQ(lines.size(), 7u);
  for (std::size_t i = 1; i < at_ms.size(); ++i)
    EXPECT_GE(at_ms[i] - at_ms[i - 1], 10'000) << i;
  EXPECT_EQ(lines[0].rfind("overrun: 3 tick(s) skipped (the first), 3 since start", 0), 0u)
      << lines[0];
  // Each later line counts what was skipped since the line before: 100 polls of 3.
  EXPECT_EQ(lines[1].rfind("overrun: 300 tick(s) skipped in the last 10 s, 303 since start", 0), 0u)
      << lines[1];
  for (const std::string& line : lines) {
    EXPECT_NE(line.find("rigidctl rate"), std::string::npos) << line;
    EXPECT_NE(line.find("--threads"), std::string::npos) << line;
    EXPECT_NE(line.find("docs/realtime-loop.md"), std::string::npos) << line;
    EXPECT_EQ(line.find('\n'), std::string::npos) << line;
  }
}

TEST(OverrunLog, NothingWhileNoTickIsSkippedAndTheNextAfterAQuietSpellAtOnce) {
  OverrunLog log;
  EXPECT_FALSE(log.update(0, 0));
  ASSERT_TRUE(log.update(5, 100 * kMs));
  for (std::int64_t t = 200; t < 60'000; t += 100)
    EXPECT_FALSE(log.update(5, t * kMs)) << t;  // the count stays: nothing new to say
  // Quiet for more than an interval: a new overrun is told when it happens.
  const auto line = log.update(6, 60'000 * kMs);
  ASSERT_TRUE(line);
  EXPECT_EQ(line->rfind("overrun: 1 tick(s) skipped in the last 60 s, 6 since start", 0), 0u)
      << *line;
}

}  // namespace
}  // namespace rigid::loop
