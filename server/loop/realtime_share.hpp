// Whether a real-time thread keeps its real-time priority, by the share of a CPU it takes.
//
// Why: rigidd's loop and its publishers share one CPU at SCHED_FIFO (server.cpp), so that a state
// leaves within ~100 us of its tick. A small world's publisher takes a few percent of that CPU,
// but a large world's can take most of it (10 MB states sent after nearly every tick, the more so
// where LCM's multicast leaves through a network interface rather than lo). Real-time threads
// that leave a CPU's normal threads nothing make the kernel take the CPU from them for those
// threads in one piece (sched_rt_runtime_us: at most 950 ms of each second; since Linux 6.12 the
// fair server's 50 ms), and the loop then wakes tens of milliseconds late (bench/notes/
// loop-latency.md, "Publishers at 10^5 bodies"). So a publisher that takes more than `limit` of a
// CPU over a window steps down to normal priority, where it still uses whatever the loop leaves
// but cannot starve the CPU, and steps back up once it takes less than `resume`.
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
