// The last sequence number seen from each command source, so that a command whose sequence number
// does not increase (a replay, a duplicate from a second bus, a restarted controller reusing
// numbers) is refused. Fixed capacity: when full, the source heard from least recently is
// forgotten (its next command is then accepted as from a new source).
#pragma once

#include <cstdint>

#include "util/fixed_map.hpp"

namespace rigid::loop {

class SequenceTable {
 public:
  explicit SequenceTable(std::size_t capacity) : map_(capacity) {}

  // true, and `seq` becomes the source's last one, if seq is above the source's last one (or the
  // source is new); false otherwise, with the last one in *last.
  bool accept(std::int64_t source, std::int64_t seq, std::int64_t* last);

  std::size_t size() const { return map_.size(); }
  void clear() { map_.clear(); }

 private:
  struct Entry {
    std::int64_t last_seq = 0;
    std::uint64_t last_use = 0;  // value of use_counter_ when last heard from
  };
  struct Hash {
    std::uint64_t operator()(std::int64_t source) const {
      return util::mix64(static_cast<std::uint64_t>(source));
    }
  };
  void evict_least_recent();

  util::FixedMap<std::int64_t, Entry, Hash> map_;
  std::uint64_t use_counter_ = 0;
};

}  // namespace rigid::loop
