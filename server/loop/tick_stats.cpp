#include "loop/tick_stats.hpp"

namespace rigid::loop {
namespace {

double us(std::int64_t ns) {
  return static_cast<double>(ns) * 1e-3;
}

}  // namespace

TickStats::TickStats(double tick_dt, std::int64_t start_ns, std::int64_t window_ns)
    : tick_dt_(tick_dt), start_ns_(start_ns), window_ns_(window_ns), window_start_ns_(start_ns) {}

LoopSummary TickStats::close_window(std::int64_t now_ns, std::int64_t tick, double sim_time,
                                    rigid::Mode mode, bool paused) {
  LoopSummary s;
  s.tick = tick;
  s.sim_time = sim_time;
  s.mode = mode;
  s.paused = paused;
  const double window_s = static_cast<double>(now_ns - window_start_ns_) * 1e-9;
  const double run_s = static_cast<double>(now_ns - start_ns_) * 1e-9;
  const auto window_ticks = static_cast<double>(ticks_stepped_ - window_start_ticks_);
  s.rtf_last_second = window_s > 0.0 ? window_ticks * tick_dt_ / window_s : 0.0;
  s.rtf_since_start = run_s > 0.0 ? static_cast<double>(ticks_stepped_) * tick_dt_ / run_s : 0.0;
  s.lateness_p50_us = us(lateness_.percentile(0.50));
  s.lateness_p99_us = us(lateness_.percentile(0.99));
  s.lateness_max_us = us(lateness_.max());
  s.overruns = overruns_;
  s.step_cost_p50_us = us(step_cost_.percentile(0.50));
  s.step_cost_max_us = us(step_cost_.max());
  s.ticks_stepped = ticks_stepped_;

  lateness_total_.merge(lateness_);
  step_cost_total_.merge(step_cost_);
  lateness_.clear();
  step_cost_.clear();
  window_start_ns_ = now_ns;
  window_start_ticks_ = ticks_stepped_;
  return s;
}

RunTotals TickStats::totals(std::int64_t now_ns) const {
  RunTotals t;
  t.ticks_stepped = ticks_stepped_;
  t.wall_s = static_cast<double>(now_ns - start_ns_) * 1e-9;
  t.sim_s_stepped = static_cast<double>(ticks_stepped_) * tick_dt_;
  t.overruns = overruns_;
  t.lateness = lateness_total_;
  t.lateness.merge(lateness_);
  t.step_cost = step_cost_total_;
  t.step_cost.merge(step_cost_);
  return t;
}

}  // namespace rigid::loop
