#include "loop/wrench_table.hpp"

#include <algorithm>
#include <cmath>

namespace rigid::loop {

std::int64_t ticks_to_live(double ttl, double tick_dt) {
  const double ratio = ttl / tick_dt;
  const double nearest = std::round(ratio);
  const double ticks =
      std::abs(ratio - nearest) <= 1e-9 * std::max(1.0, nearest) ? nearest : std::ceil(ratio);
  return std::max<std::int64_t>(1, static_cast<std::int64_t>(ticks));
}

WrenchTable::WrenchTable(std::size_t capacity) : entries_(capacity), index_(capacity) {}

WrenchTable::Upsert WrenchTable::upsert(const Wrench& wrench, std::int64_t expires_at_tick) {
  const Key key = key_of(wrench);
  if (const std::uint32_t* at = index_.find(key)) {
    entries_[*at] = ActiveWrench{wrench, expires_at_tick};
    return Upsert::kReplaced;
  }
  if (size_ >= entries_.size()) return Upsert::kFull;
  entries_[size_] = ActiveWrench{wrench, expires_at_tick};
  index_.put(key, static_cast<std::uint32_t>(size_));
  ++size_;
  return Upsert::kInserted;
}

std::size_t WrenchTable::expire(std::int64_t tick) {
  // Stable compaction: survivors keep their relative order; moved ones get their new position.
  std::size_t kept = 0;
  for (std::size_t i = 0; i < size_; ++i) {
    const ActiveWrench& e = entries_[i];
    if (e.expires_at_tick <= tick) {
      index_.erase(key_of(e.wrench));
      continue;
    }
    if (kept != i) {
      entries_[kept] = e;
      index_.put(key_of(e.wrench), static_cast<std::uint32_t>(kept));
    }
    ++kept;
  }
  const std::size_t dropped = size_ - kept;
  size_ = kept;
  return dropped;
}

void WrenchTable::clear() {
  size_ = 0;
  index_.clear();
}

}  // namespace rigid::loop
