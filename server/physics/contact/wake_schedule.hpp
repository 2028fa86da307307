// The step at which each body must next be looked at by the contact stage: a min-heap of
// (step, body) with lazy deletion (a body rescheduled leaves its old entry behind, recognised as
// stale by its stamp). Capacity for two entries a body is reserved up front and the heap is
// compacted in place when it fills, so that scheduling while stepping never allocates.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

namespace rigid::physics::contact {

class WakeSchedule {
 public:
  static constexpr std::int64_t kNever = INT64_MAX;

  void reset(int bodies) {
    heap_.clear();
    heap_.reserve(2 * static_cast<std::size_t>(bodies) + 16);
    stamp_.assign(static_cast<std::size_t>(bodies), 0);
    when_.assign(static_cast<std::size_t>(bodies), kNever);
  }
  // A copied schedule keeps its entries, not its capacity.
  void reserve() { heap_.reserve(2 * stamp_.size() + 16); }

  // Body id is next due at `step` (kNever: not until rescheduled).
  void at(int id, std::int64_t step) {
    const auto k = static_cast<std::size_t>(id);
    ++stamp_[k];
    when_[k] = step;
    if (step == kNever) return;
    if (heap_.size() == heap_.capacity()) compact();
    heap_.push_back(Entry{step, id, stamp_[k]});
    std::push_heap(heap_.begin(), heap_.end(), Later{});
  }
  std::int64_t when(int id) const { return when_[static_cast<std::size_t>(id)]; }

  // Calls f(id) once for every body due at or before `step` (in order of due step, then id), and
  // unschedules it: f schedules it again.
  template <class F>
  void take_due(std::int64_t step, F&& f) {
    while (!heap_.empty() && heap_.front().step <= step) {
      std::pop_heap(heap_.begin(), heap_.end(), Later{});
      const Entry e = heap_.back();
      heap_.pop_back();
      const auto k = static_cast<std::size_t>(e.id);
      if (e.stamp != stamp_[k]) continue;  // stale
      ++stamp_[k];
      when_[k] = kNever;
      f(e.id);
    }
  }

 private:
  struct Entry {
    std::int64_t step;
    int id;
    std::uint32_t stamp;
  };
  // A min-heap by (step, id): std::*_heap keep the largest first.
  struct Later {
    bool operator()(const Entry& a, const Entry& b) const {
      return a.step != b.step ? a.step > b.step : a.id > b.id;
    }
  };
  // Drops the stale entries (at most one live entry a body remains).
  void compact() {
    const auto live = [&](const Entry& e) {
      return e.stamp == stamp_[static_cast<std::size_t>(e.id)];
    };
    heap_.erase(std::partition(heap_.begin(), heap_.end(), live), heap_.end());
    std::make_heap(heap_.begin(), heap_.end(), Later{});
  }

  std::vector<Entry> heap_;
  std::vector<std::uint32_t> stamp_;
  std::vector<std::int64_t> when_;
};

}  // namespace rigid::physics::contact
