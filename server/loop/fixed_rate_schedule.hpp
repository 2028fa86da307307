// The deadlines of a fixed-rate loop, as arithmetic only (no clock, no sleeping), so it can be
// tested exactly.
//
// Slot k is due at origin + round(k * period): every deadline is computed from the origin, never
// by adding periods, so rounding never accumulates and a late tick never shifts the ones after it.
//
// Overrun policy: count and skip. When a tick ends after the next slot's deadline, the slots whose
// deadlines have passed are skipped (not run late, not caught up in a burst) and counted as
// overruns; the loop sleeps to the first deadline still ahead. Simulated time is tick * dt, so
// it simply falls behind the wall clock by the skipped slots.
#pragma once

#include <cstdint>

namespace rigid::loop {

class FixedRateSchedule {
 public:
  // The first slot (0) is due at `origin_ns`. period_ns > 0.
  FixedRateSchedule(std::int64_t origin_ns, double period_ns);

  std::int64_t slot() const { return slot_; }
  double period_ns() const { return period_ns_; }
  std::int64_t deadline() const { return deadline_of(slot_); }
  std::int64_t deadline_of(std::int64_t slot) const;

  // The current slot's tick ended at `now_ns`: moves to the next slot whose deadline has not
  // passed (now_ns <= deadline) and returns how many slots were skipped to get there (0 when the
  // next deadline is still ahead or exactly now).
  std::int64_t advance(std::int64_t now_ns);

  // Starts over: slot 0 due at origin_ns, with a new period (a resume, a new real-time factor).
  void restart(std::int64_t origin_ns, double period_ns);

 private:
  std::int64_t origin_ns_;
  double period_ns_;
  std::int64_t slot_ = 0;
};

}  // namespace rigid::loop
