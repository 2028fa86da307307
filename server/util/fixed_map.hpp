// A hash map with a capacity fixed at construction: open addressing, linear probing and
// backward-shift deletion (no tombstones), so it never allocates after construction and never
// degrades with churn. For the loop's per-tick tables (wrench keys, per-source sequence numbers).
// Keys are trivially copyable and compared with ==; Hash maps a key to 64 well-mixed bits.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <vector>

namespace rigid::util {

// splitmix64's finaliser: spreads sequential ids over the table.
inline std::uint64_t mix64(std::uint64_t x) {
  x ^= x >> 30;
  x *= 0xbf58476d1ce4e5b9ULL;
  x ^= x >> 27;
  x *= 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

template <class Key, class Value, class Hash>
class FixedMap {
  static_assert(std::is_trivially_copyable_v<Key> && std::is_trivially_copyable_v<Value>);

 public:
  // Holds up to max_size entries; the table has at least twice as many slots, so probes stay short.
  explicit FixedMap(std::size_t max_size)
      : max_size_(max_size), slots_(std::bit_ceil(2 * (max_size < 1 ? 1 : max_size))) {}

  std::size_t size() const { return size_; }
  std::size_t max_size() const { return max_size_; }
  bool full() const { return size_ >= max_size_; }

  Value* find(const Key& key) {
    for (std::size_t i = home(key);; i = next(i)) {
      Slot& s = slots_[i];
      if (!s.used) return nullptr;
      if (s.key == key) return &s.value;
    }
  }

  // Inserts or overwrites. false (and nothing changes) when the key is new and the map is full.
  bool put(const Key& key, const Value& value) {
    std::size_t i = home(key);
    for (;; i = next(i)) {
      Slot& s = slots_[i];
      if (!s.used) break;
      if (s.key == key) {
        s.value = value;
        return true;
      }
    }
    if (full()) return false;
    slots_[i] = Slot{key, value, true};
    ++size_;
    return true;
  }

  // false if the key was not there.
  bool erase(const Key& key) {
    std::size_t hole = home(key);
    for (;; hole = next(hole)) {
      if (!slots_[hole].used) return false;
      if (slots_[hole].key == key) break;
    }
    // Backward shift: pull later entries of the probe run into the hole when their home position
    // allows it, so lookups never stop early at an emptied slot.
    for (std::size_t i = next(hole);; i = next(i)) {
      Slot& s = slots_[i];
      if (!s.used) break;
      const std::size_t h = home(s.key);
      // s may move to `hole` if its home is not cyclically within (hole, i].
      const bool stays = hole <= i ? (hole < h && h <= i) : (hole < h || h <= i);
      if (!stays) {
        slots_[hole] = s;
        hole = i;
      }
    }
    slots_[hole].used = false;
    --size_;
    return true;
  }

  void clear() {
    for (Slot& s : slots_)
      s.used = false;
    size_ = 0;
  }

  // Calls f(key, value&) for every entry, in table order.
  template <class F>
  void for_each(F&& f) {
    for (Slot& s : slots_)
      if (s.used) f(s.key, s.value);
  }

 private:
  struct Slot {
    Key key{};
    Value value{};
    bool used = false;
  };
  std::size_t home(const Key& key) const { return Hash{}(key) & (slots_.size() - 1); }
  std::size_t next(std::size_t i) const { return (i + 1) & (slots_.size() - 1); }

  std::size_t max_size_;
  std::size_t size_ = 0;
  std::vector<Slot> slots_;
};

}  // namespace rigid::util
