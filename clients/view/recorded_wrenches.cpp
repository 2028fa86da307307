#include "recorded_wrenches.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "common/wrench_table.hpp"

namespace rigid::view {
namespace {

// States recorded in a new stretch after which a stretch the command stream never explained (no
// reset: rigidd restarted) is taken as such: a reset's command is never that late.
constexpr std::uint32_t kOwedStates = 1000;
// The largest tick and number of ticks taken from a file (exact in a double; no overflow).
constexpr std::int64_t kMaxTick = std::int64_t{1} << 53;
constexpr double kMaxTicksToLive = 1e12;

bool before(const RecordedWrench& w, std::pair<std::uint32_t, std::int64_t> at) {
  return std::pair{w.stretch, w.command.tick} < at;
}

// rigidd's ticks for a ttl (common::ticks_to_live); -1 when dt is not known, 0 for a ttl too long
// for any scene (a file's numbers are not trusted).
std::int64_t ticks_of(double ttl, double dt) {
  if (!(std::isfinite(dt) && dt > 0)) return -1;
  if (!(ttl / dt <= kMaxTicksToLive)) return 0;
  return common::ticks_to_live(ttl, dt);
}

}  // namespace

void RecordedWrenches::state(std::int64_t tick) {
  if (any_state_ && tick < last_tick_) {
    ++states_stretch_;
    previous_last_tick_ = last_tick_;
    states_in_stretch_ = 0;
    if (pending_ > 0) {
      --pending_;  // the reset the command stream announced
    } else {
      ++owed_;  // the states are ahead of the command stream (or rigidd restarted)
    }
  }
  if (++states_in_stretch_ > kOwedStates) owed_ = 0;
  any_state_ = true;
  last_tick_ = tick;
}

void RecordedWrenches::scene_changed() {
  // A restarted rigidd: its ticks start again like after a reset.
  if (owed_ > 0) {
    --owed_;
  } else {
    ++pending_;
  }
}

std::uint32_t RecordedWrenches::stretch_of(std::int64_t tick) const {
  if (pending_ > 0) return states_stretch_ + pending_;
  if (owed_ > 0 && states_stretch_ > 0) {
    // A command accepted near the tick its rigidd had reached: the stretch whose last recorded
    // tick is nearest (ties: the newer).
    const auto distance = [tick](std::int64_t last) { return std::abs(tick - last); };
    return distance(previous_last_tick_) < distance(last_tick_) ? states_stretch_ - 1
                                                                : states_stretch_;
  }
  return states_stretch_;
}

void RecordedWrenches::command(const AcceptedCommand& a, double dt) {
  if (a.tick < 0 || a.tick > kMaxTick) return;  // not rigidd's: shown nowhere
  if (a.kind == AcceptedKind::kControl) {
    if (a.command != ControlKind::kReset) return;
    // rigidd clears its wrench table: the open wrenches of the reset's stretch end at its tick.
    const std::uint32_t stretch = stretch_of(a.tick);
    for (auto it = open_.begin(); it != open_.end();) {
      if (std::get<0>(it->first) != stretch) {
        ++it;
        continue;
      }
      RecordedWrench& w = wrenches_[it->second];
      w.until = std::min(w.until, a.tick);
      it = open_.erase(it);
    }
    // At tick 0 the ticks do not go back: no new stretch.
    if (a.tick > 0) {
      if (owed_ > 0) {
        --owed_;  // its states came first
      } else {
        ++pending_;
      }
    }
    return;
  }
  if (a.kind == AcceptedKind::kEdit) {
    if (a.edit != EditKind::kResetBody) return;
    // rigidd drops the wrenches acting on the body it resets: they end at the reset's tick.
    const std::uint32_t stretch = stretch_of(a.tick);
    for (auto it = open_.begin(); it != open_.end();) {
      if (std::get<0>(it->first) != stretch || std::get<2>(it->first) != a.body_id) {
        ++it;
        continue;
      }
      RecordedWrench& w = wrenches_[it->second];
      w.until = std::min(w.until, a.tick);
      it = open_.erase(it);
    }
    return;
  }
  if (a.kind != AcceptedKind::kWrench) return;
  if (!(std::isfinite(a.ttl) && a.ttl >= 0)) return;
  const std::int64_t ticks = ticks_of(a.ttl, dt);
  if (ticks == 0) return;  // a ttl no scene allows
  const std::uint32_t stretch = stretch_of(a.tick);
  const auto key = std::tuple{stretch, a.source, a.body_id, a.key};
  const std::size_t index = wrenches_.size();
  if (const auto it = open_.find(key); it != open_.end()) {
    RecordedWrench& older = wrenches_[it->second];  // replaced from this one's tick on
    older.until = std::min(older.until, a.tick);
    it->second = index;
  } else {
    open_.emplace(key, index);
  }
  wrenches_.push_back(RecordedWrench{a, stretch, ticks, std::numeric_limits<std::int64_t>::max()});
}

void RecordedWrenches::finish(double first_dt) {
  open_.clear();
  for (RecordedWrench& w : wrenches_) {
    if (w.ticks < 0) w.ticks = std::max<std::int64_t>(ticks_of(w.command.ttl, first_dt), 1);
    w.until = std::min(w.until, w.command.tick + w.ticks);
    longest_ = std::max(longest_, w.ticks);
  }
  // The command stream is in tick order within a stretch; only a stretch chosen by nearness can
  // be out of order, and acting() searches by (stretch, tick).
  std::stable_sort(
      wrenches_.begin(), wrenches_.end(), [](const RecordedWrench& x, const RecordedWrench& y) {
        return std::pair{x.stretch, x.command.tick} < std::pair{y.stretch, y.command.tick};
      });
}

std::vector<std::size_t> RecordedWrenches::acting(std::uint32_t stretch, std::int64_t tick,
                                                  std::size_t max) const {
  std::vector<std::size_t> out;
  if (tick <= 0 || tick > kMaxTick) return out;  // (a file's tick: no wrench acts there)
  // Only wrenches accepted at most longest_ ticks before can still act.
  const auto first = std::lower_bound(wrenches_.begin(), wrenches_.end(),
                                      std::pair{stretch, tick - longest_}, before);
  for (auto it = first; it != wrenches_.end() && it->stretch == stretch && it->command.tick < tick;
       ++it) {
    if (tick <= it->until) out.push_back(static_cast<std::size_t>(it - wrenches_.begin()));
  }
  if (out.size() > max) out.erase(out.begin(), out.end() - static_cast<std::ptrdiff_t>(max));
  return out;
}

}  // namespace rigid::view
