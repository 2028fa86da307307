#include "loop/overrun_log.hpp"

#include <cstdio>

namespace rigid::loop {

std::optional<std::string> OverrunLog::update(std::int64_t overruns, std::int64_t now_ns) {
  if (overruns <= logged_) return std::nullopt;
  if (last_ns_ && now_ns - *last_ns_ < kInterval_ns) return std::nullopt;
  const std::int64_t skipped = overruns - logged_;
  char when[64];
  if (last_ns_) {
    std::snprintf(when, sizeof when, "in the last %.0f s",
                  static_cast<double>(now_ns - *last_ns_) * 1e-9);
  } else {
    std::snprintf(when, sizeof when, "(the first)");
  }
  logged_ = overruns;
  last_ns_ = now_ns;
  return "overrun: " + std::to_string(skipped) + " tick(s) skipped " + when + ", " +
         std::to_string(overruns) +
         " since start: the loop falls behind its deadlines and simulated time lags the wall "
         "clock; lower the rate (rigidctl rate X) or the scene's load, give the step more "
         "--threads, or see docs/realtime-loop.md (at most one such line per " +
         std::to_string(kInterval_ns / 1'000'000'000) + " s)";
}

}  // namespace rigid::loop
