// The wrenches acting on the world: one entry per (source, body, key), a newer wrench with the same
// key replacing the older one. Each lives for its time to live in simulated time, counted in ticks
// (0 s: the next tick only), and then drops out, so a controller that dies stops pushing within
// its ttl. Fixed capacity; entries stay in arrival order, so the forces are summed in the same
// order for the same commands and the simulation stays deterministic.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "loop/command.hpp"
#include "loop/fixed_map.hpp"

namespace rigid::loop {

// The number of ticks a wrench with time to live `ttl` (s) acts for, at `tick_dt` (s) per tick:
// ttl / tick_dt rounded up (a ratio within 1e-9 of an integer counts as that integer, so 0.2 s
// at 1 ms is 200 ticks, not 201), and at least 1.
std::int64_t ticks_to_live(double ttl, double tick_dt);

struct ActiveWrench {
  Wrench wrench;
  std::int64_t expires_at_tick = 0;  // acts while the tick counter is below this
};

class WrenchTable {
 public:
  explicit WrenchTable(std::size_t capacity);

  enum class Upsert : std::uint8_t { kInserted, kReplaced, kFull };
  // Adds the wrench, or replaces the one with the same (source, body, key) (keeping its place in
  // the order). kFull: a new key and no room; the table is unchanged.
  Upsert upsert(const Wrench& wrench, std::int64_t expires_at_tick);
  // Drops the entries with expires_at_tick <= tick. Returns how many were dropped.
  std::size_t expire(std::int64_t tick);
  void clear();

  std::span<const ActiveWrench> active() const { return {entries_.data(), size_}; }
  std::size_t size() const { return size_; }
  std::size_t capacity() const { return entries_.size(); }

 private:
  struct Key {
    std::int64_t source;
    std::int32_t body;
    std::int32_t key;
    bool operator==(const Key&) const = default;
  };
  struct KeyHash {
    std::uint64_t operator()(const Key& k) const {
      return mix64(static_cast<std::uint64_t>(k.source) ^
                   mix64((static_cast<std::uint64_t>(static_cast<std::uint32_t>(k.body)) << 32) |
                         static_cast<std::uint32_t>(k.key)));
    }
  };
  static Key key_of(const Wrench& w) { return Key{w.source, w.body, w.key}; }

  std::vector<ActiveWrench> entries_;  // the first size_ are live, in arrival order
  std::size_t size_ = 0;
  FixedMap<Key, std::uint32_t, KeyHash> index_;  // key -> position in entries_
};

}  // namespace rigid::loop
