// The loop's timing figures: lateness of each tick against its absolute deadline (realtime mode),
// the cost of each tick's physics, overruns, and the simulated time achieved. Figures are gathered
// in a one-second window (what Stats reports each second) and folded into totals for the whole
// run (what rigidd logs when it stops). Fixed-size histograms: recording allocates nothing.
#pragma once

#include <cstdint>

#include "loop/histogram.hpp"
#include "rigid/messages.hpp"

namespace rigid::loop {

// One window's figures, handed from the loop thread to the Stats publisher.
struct LoopSummary {
  std::int64_t tick = 0;
  double sim_time = 0.0;
  rigid::Mode mode = rigid::Mode::kRealtime;
  bool paused = false;
  double rtf_last_second = 0.0;
  double rtf_since_start = 0.0;
  double lateness_p50_us = 0.0;
  double lateness_p99_us = 0.0;
  double lateness_max_us = 0.0;
  std::int64_t overruns = 0;  // since start
  double step_cost_p50_us = 0.0;
  double step_cost_max_us = 0.0;
  std::int64_t ticks_stepped = 0;  // since start (resets do not rewind it)
  // Physics faults (set by the loop, which owns the world): bodies the guard holds frozen now,
  // and body-steps that turned by more than pi since start (resets do not rewind it).
  std::int64_t bodies_frozen = 0;
  std::int64_t large_rotation_steps = 0;
};

// The whole run, for the closing log line and the benchmark.
struct RunTotals {
  std::int64_t ticks_stepped = 0;
  double wall_s = 0.0;
  double sim_s_stepped = 0.0;  // ticks_stepped * tick_dt
  std::int64_t overruns = 0;
  Histogram lateness;   // ns
  Histogram step_cost;  // ns
};

class TickStats {
 public:
  TickStats(double tick_dt, std::int64_t start_ns, std::int64_t window_ns = 1'000'000'000);

  void record_lateness(std::int64_t ns) { lateness_.record(ns); }
  void record_step_cost(std::int64_t ns) { step_cost_.record(ns); }
  void add_overruns(std::int64_t n) { overruns_ += n; }
  void count_tick() { ++ticks_stepped_; }

  std::int64_t overruns() const { return overruns_; }
  std::int64_t ticks_stepped() const { return ticks_stepped_; }
  std::int64_t window_end_ns() const { return window_start_ns_ + window_ns_; }
  bool window_due(std::int64_t now_ns) const { return now_ns >= window_end_ns(); }

  // Summarises the window ending at now_ns, folds it into the totals, and opens the next one.
  LoopSummary close_window(std::int64_t now_ns, std::int64_t tick, double sim_time,
                           rigid::Mode mode, bool paused);

  // The totals, including the open window, as of now_ns.
  RunTotals totals(std::int64_t now_ns) const;

 private:
  double tick_dt_;
  std::int64_t start_ns_;
  std::int64_t window_ns_;
  std::int64_t window_start_ns_;
  std::int64_t window_start_ticks_ = 0;
  std::int64_t ticks_stepped_ = 0;
  std::int64_t overruns_ = 0;
  Histogram lateness_;  // the open window
  Histogram step_cost_;
  Histogram lateness_total_;  // closed windows
  Histogram step_cost_total_;
};

}  // namespace rigid::loop
