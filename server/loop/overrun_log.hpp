// What rigidd's log says about skipped ticks (overruns: the loop fell behind its deadlines). On a
// busy host they come every second for as long as it stays busy; a line per second would bury
// every other event. So the first overrun is told at once, and after it at most one line per
// kInterval sums up the ticks skipped since the last line, each with what to do about it.
// Used by the housekeeping thread only (the loop counts, server.cpp asks this what to log).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace rigid::loop {

class OverrunLog {
 public:
  static constexpr std::int64_t kInterval_ns = 10'000'000'000;

  // `overruns`: the loop's count since start; `now_ns`: CLOCK_MONOTONIC. The line to log now, if
  // any (without a trailing newline).
  std::optional<std::string> update(std::int64_t overruns, std::int64_t now_ns);

 private:
  std::int64_t logged_ = 0;              // overruns already told
  std::optional<std::int64_t> last_ns_;  // when the last line was
};

}  // namespace rigid::loop
