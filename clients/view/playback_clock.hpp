// rigid-view FILE: where playback is on a recording's timeline (recording_source.hpp), as a pure
// function of the wall clock: playing at `speed`, the position advances by speed * elapsed wall
// time; the state shown is the last one whose position is at or before it. Reaching the end
// pauses on the last state. No I/O and no clock of its own: the caller passes `now`, so the tests
// drive it with made-up times.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "recording_source.hpp"

namespace rigid::view {

class PlaybackClock {
 public:
  using Clock = std::chrono::steady_clock;

  // `states` must outlive the clock, be non-empty, with non-decreasing positions.
  explicit PlaybackClock(const std::vector<RecordedState>& states);

  // Where the position is at `now`; at the end while playing, pauses there.
  std::size_t current(Clock::time_point now);
  double position(Clock::time_point now) const;

  // Playing from the start again when paused at the end.
  void play(Clock::time_point now);
  void pause(Clock::time_point now);
  void set_speed(double speed, Clock::time_point now);
  // The state shown afterwards: the one nearest to `time` on the timeline (a slider's value is
  // rounded to fewer digits than a state's time: "at or before" would land on the one before).
  std::size_t seek_time(double time, Clock::time_point now);
  // The first state with this tick, or, when none has it, the one whose tick is nearest (the
  // earliest of equals). Ticks may repeat when the recording holds a reset.
  std::size_t seek_tick(std::int64_t tick, Clock::time_point now);

  bool playing() const { return playing_; }
  double speed() const { return speed_; }
  double start() const { return states_.front().position; }
  double end() const { return states_.back().position; }

 private:
  std::size_t index_at(double position) const;
  void seek_index(std::size_t i, Clock::time_point now);

  const std::vector<RecordedState>& states_;
  bool playing_ = false;
  double speed_ = 1;
  double anchor_position_ = 0;     // the position at anchor_time_
  Clock::time_point anchor_time_;  // when it was anchored (play, seek, speed)
  // Shown while paused: exactly the state sought, even where several share its position.
  std::size_t held_ = 0;
};

}  // namespace rigid::view
