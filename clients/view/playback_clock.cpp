#include "playback_clock.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>

namespace rigid::view {

PlaybackClock::PlaybackClock(const std::vector<RecordedState>& states) : states_(states) {
  anchor_position_ = states_.front().position;
}

double PlaybackClock::position(Clock::time_point now) const {
  if (!playing_) return states_[held_].position;
  const double elapsed = std::chrono::duration<double>(now - anchor_time_).count();
  return std::min(anchor_position_ + speed_ * std::max(elapsed, 0.0), end());
}

std::size_t PlaybackClock::index_at(double position) const {
  // The last state at or before `position` (positions do not decrease: binary search).
  const auto after =
      std::upper_bound(states_.begin(), states_.end(), position,
                       [](double p, const RecordedState& s) { return p < s.position; });
  return after == states_.begin() ? 0 : static_cast<std::size_t>(after - states_.begin()) - 1;
}

std::size_t PlaybackClock::current(Clock::time_point now) {
  if (!playing_) return held_;
  const double p = position(now);
  if (p >= end()) {
    playing_ = false;
    held_ = states_.size() - 1;
    return held_;
  }
  return index_at(p);
}

void PlaybackClock::play(Clock::time_point now) {
  if (playing_) return;
  if (held_ + 1 >= states_.size()) held_ = 0;  // at the end: from the start
  anchor_position_ = states_[held_].position;
  anchor_time_ = now;
  playing_ = true;
}

void PlaybackClock::pause(Clock::time_point now) {
  if (!playing_) return;
  held_ = current(now);
  playing_ = false;
}

void PlaybackClock::set_speed(double speed, Clock::time_point now) {
  if (playing_) {  // re-anchor, so that the position does not jump
    anchor_position_ = position(now);
    anchor_time_ = now;
  }
  speed_ = speed;
}

void PlaybackClock::seek_index(std::size_t i, Clock::time_point now) {
  held_ = i;
  anchor_position_ = states_[i].position;
  anchor_time_ = now;
}

std::size_t PlaybackClock::seek_time(double time, Clock::time_point now) {
  std::size_t i = index_at(time);
  if (i + 1 < states_.size() &&
      std::abs(states_[i + 1].position - time) < std::abs(time - states_[i].position))
    ++i;
  seek_index(i, now);
  return i;
}

std::size_t PlaybackClock::seek_tick(std::int64_t tick, Clock::time_point now) {
  std::size_t best = 0;
  std::int64_t best_distance = -1;
  for (std::size_t i = 0; i < states_.size(); ++i) {  // ticks may repeat (resets): a scan
    const std::int64_t d = std::abs(states_[i].tick - tick);
    if (best_distance < 0 || d < best_distance) {
      best = i;
      best_distance = d;
      if (d == 0) break;
    }
  }
  seek_index(best, now);
  return best;
}

}  // namespace rigid::view
