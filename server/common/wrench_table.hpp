// The wrenches acting on the world: one entry per (owner, source, body, key), a newer wrench with
// the same key replacing the older one. Each sender (command.hpp: an identity or a client session)
// holds at most its share of the entries; when the table is full, a sender below its share takes
// the oldest entry of the sender holding the most (so a newcomer always gets in, however many
// senders flood the table), and a sender at its share is refused. Each lives for its time to live
// in simulated time, counted in ticks (0 s: the next tick only), and then drops out, so a
// controller that dies stops pushing within its ttl. Fixed capacity; entries stay in arrival order,
// so the forces are summed in the same order for the same commands and the simulation stays
// deterministic.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "common/applied_command.hpp"
#include "util/fixed_map.hpp"

namespace rigid::common {

// The number of ticks a wrench with time to live `ttl` (s) acts for, at `tick_dt` (s) per tick:
// ttl / tick_dt rounded up (a ratio within 1e-9 of an integer counts as that integer, so 0.2 s
// at 1 ms is 200 ticks, not 201), and at least 1.
std::int64_t ticks_to_live(double ttl, double tick_dt);

struct ActiveWrench {
  Wrench wrench;
  std::int64_t expires_at_tick = 0;  // acts while the tick counter is below this
  std::uint64_t sender = 0;          // Sender::key, whose share it counts against
};

class WrenchTable {
 public:
  explicit WrenchTable(std::size_t capacity);

  enum class Upsert : std::uint8_t { kInserted, kReplaced, kFull, kOverShare };
  // Adds the wrench, or replaces the one with the same (owner, source, body, key) (keeping its
  // place in the order). kOverShare: a new key from a sender already holding `share` entries;
  // kFull: a new key, no room, and no sender holding more than this one could give way. The
  // table is then unchanged. A replacement by another sender moves the entry to that sender.
  Upsert upsert(const Wrench& wrench, std::uint64_t sender, std::size_t share,
                std::int64_t expires_at_tick);
  // The entries `sender` holds.
  std::size_t held_by(std::uint64_t sender);
  // Drops the entries with expires_at_tick <= tick. Returns how many were dropped.
  std::size_t expire(std::int64_t tick);
  // Drops the entries on `body` (the others keep their order). Returns how many were dropped.
  std::size_t drop_body(std::int32_t body);
  void clear();

  std::span<const ActiveWrench> active() const { return {entries_.data(), size_}; }
  std::size_t size() const { return size_; }
  std::size_t capacity() const { return entries_.size(); }

 private:
  struct Key {
    std::uint64_t owner;
    std::int64_t source;
    std::int32_t body;
    std::int32_t key;
    bool operator==(const Key&) const = default;
  };
  struct KeyHash {
    std::uint64_t operator()(const Key& k) const {
      return util::mix64(
          k.owner ^ util::mix64(static_cast<std::uint64_t>(k.source)) ^
          util::mix64((static_cast<std::uint64_t>(static_cast<std::uint32_t>(k.body)) << 32) |
                      static_cast<std::uint32_t>(k.key)));
    }
  };
  struct SenderHash {
    std::uint64_t operator()(std::uint64_t k) const { return util::mix64(k); }
  };
  static Key key_of(const Wrench& w) { return Key{w.owner, w.source, w.body, w.key}; }
  // Drops the entries for which drop(entry) is true, keeping the others' order.
  template <class Drop>
  std::size_t drop_where(Drop drop);
  void count(std::uint64_t sender, int delta);
  // Removes the oldest entry of the sender holding the most entries if it holds more than
  // `than` + 1; false if none does.
  bool evict_from_largest(std::size_t than);

  std::vector<ActiveWrench> entries_;  // the first size_ are live, in arrival order
  std::size_t size_ = 0;
  util::FixedMap<Key, std::uint32_t, KeyHash> index_;              // key -> position in entries_
  util::FixedMap<std::uint64_t, std::uint32_t, SenderHash> held_;  // sender -> entries held
};

}  // namespace rigid::common
