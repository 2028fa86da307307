// Whether a real-time thread keeps its real-time priority, by the share of a CPU it takes.
//
// Why: rigidd's loop and its publishers share one CPU at SCHED_FIFO (server.cpp), so that a state
// leaves within ~100 us of its tick. A small world's publisher takes 1-2% of that CPU and one of
// 10^5 bodies 20-21%, but where LCM's multicast leaves through a network interface rather than lo
// (a host with a NIC and no multicast route on lo) the LCM publisher of 10^5 bodies (10.8 MB a
// state, sent as often as every tick while commands come in) took 45-63% beside the loop's 25-31%
// (per-thread CPU time from /proc, loop_bench realtime at 10^5 bodies, 100 Hz, both buses).
// Real-time threads that leave a CPU's normal threads nothing make the kernel take the CPU from
// them for those threads in one piece (sched_rt_runtime_us: at most 950 ms of each second; since
// Linux 6.12 the fair server's 50 ms): the loop then woke up to 51 ms late and skipped 102 ticks
// in a minute, where with the publishers stepped down it woke at most 7.7 ms late and skipped 2
// (side by side, README "Larger worlds"). So a publisher that takes more than `limit` of a CPU
// over a window steps down to normal priority, where it still uses whatever the loop leaves but
// cannot starve the CPU, and steps back up once it takes less than `resume`.
#pragma once

#include <cstdint>

namespace rigid::loop {

class RealtimeShare {
 public:
  enum class Change { kNone, kStepDown, kStepUp };

  // 0 < resume < limit <= 1 (shares of one CPU); window_ns > 0.
  RealtimeShare(double limit, double resume, std::int64_t window_ns);

  // The thread's CPU time so far (CLOCK_THREAD_CPUTIME_ID) and the time now (CLOCK_MONOTONIC),
  // in ns, from the thread itself. The first call starts a window; a window closes at the first
  // call window_ns or more after it started, and its share (CPU time over wall time) decides.
  // Readings that go backwards start a new window and change nothing.
  Change update(std::int64_t thread_cpu_ns, std::int64_t now_ns);

  bool stepped_down() const { return down_; }
  // The share of the last window closed (0 before any).
  double last_share() const { return last_share_; }

 private:
  double limit_;
  double resume_;
  std::int64_t window_ns_;
  bool started_ = false;
  bool down_ = false;
  std::int64_t cpu0_ = 0;
  std::int64_t wall0_ = 0;
  double last_share_ = 0.0;
};

}  // namespace rigid::loop
