#include "common/wrench_table.hpp"

#include <algorithm>
#include <cmath>

namespace rigid::common {

std::int64_t ticks_to_live(double ttl, double tick_dt) {
  const double ratio = ttl / tick_dt;
  const double nearest = std::round(ratio);
  const double ticks =
      std::abs(ratio - nearest) <= 1e-9 * std::max(1.0, nearest) ? nearest : std::ceil(ratio);
  return std::max<std::int64_t>(1, static_cast<std::int64_t>(ticks));
}

WrenchTable::WrenchTable(std::size_t capacity)
    : entries_(capacity), index_(capacity), held_(capacity) {}

void WrenchTable::count(std::uint64_t sender, int delta) {
  std::uint32_t* n = held_.find(sender);
  if (n == nullptr) {
    held_.put(sender, static_cast<std::uint32_t>(delta));  // delta > 0: a sender holds <= capacity
    return;
  }
  *n = static_cast<std::uint32_t>(static_cast<std::int64_t>(*n) + delta);
  if (*n == 0) held_.erase(sender);
}

std::size_t WrenchTable::held_by(std::uint64_t sender) {
  const std::uint32_t* n = held_.find(sender);
  return n == nullptr ? 0 : *n;
}

bool WrenchTable::evict_from_largest(std::size_t than) {
  std::uint64_t largest = 0;
  std::uint32_t most = 0;
  held_.for_each([&](std::uint64_t sender, std::uint32_t n) {
    if (n > most) {
      most = n;
      largest = sender;
    }
  });
  if (most <= than + 1) return false;
  // Its oldest entry goes; the rest keep their order (stable compaction from there).
  std::size_t i = 0;
  while (entries_[i].sender != largest)
    ++i;
  index_.erase(key_of(entries_[i].wrench));
  count(largest, -1);
  for (; i + 1 < size_; ++i) {
    entries_[i] = entries_[i + 1];
    index_.put(key_of(entries_[i].wrench), static_cast<std::uint32_t>(i));
  }
  --size_;
  return true;
}

WrenchTable::Upsert WrenchTable::upsert(const Wrench& wrench, std::uint64_t sender,
                                        std::size_t share, std::int64_t expires_at_tick) {
  const Key key = key_of(wrench);
  if (const std::uint32_t* at = index_.find(key)) {
    ActiveWrench& e = entries_[*at];
    if (e.sender != sender) {
      count(e.sender, -1);
      count(sender, +1);
    }
    e = ActiveWrench{wrench, expires_at_tick, sender};
    return Upsert::kReplaced;
  }
  const std::size_t held = held_by(sender);
  if (held >= share) return Upsert::kOverShare;
  if (size_ >= entries_.size() && !evict_from_largest(held)) return Upsert::kFull;
  entries_[size_] = ActiveWrench{wrench, expires_at_tick, sender};
  index_.put(key, static_cast<std::uint32_t>(size_));
  count(sender, +1);
  ++size_;
  return Upsert::kInserted;
}

std::size_t WrenchTable::expire(std::int64_t tick) {
  return drop_where([tick](const ActiveWrench& e) { return e.expires_at_tick <= tick; });
}

std::size_t WrenchTable::drop_body(std::int32_t body) {
  return drop_where([body](const ActiveWrench& e) { return e.wrench.body == body; });
}

template <class Drop>
std::size_t WrenchTable::drop_where(Drop drop) {
  // Stable compaction: survivors keep their relative order; moved ones get their new position.
  std::size_t kept = 0;
  for (std::size_t i = 0; i < size_; ++i) {
    const ActiveWrench& e = entries_[i];
    if (drop(e)) {
      index_.erase(key_of(e.wrench));
      count(e.sender, -1);
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
  held_.clear();
}

}  // namespace rigid::common
