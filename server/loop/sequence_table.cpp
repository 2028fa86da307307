#include "loop/sequence_table.hpp"

namespace rigid::loop {

bool SequenceTable::accept(std::int64_t source, std::int64_t seq, std::int64_t* last) {
  ++use_counter_;
  if (Entry* e = map_.find(source)) {
    if (seq <= e->last_seq) {
      *last = e->last_seq;
      return false;
    }
    *e = Entry{seq, use_counter_};
    return true;
  }
  if (map_.full()) evict_least_recent();
  map_.put(source, Entry{seq, use_counter_});
  return true;
}

void SequenceTable::evict_least_recent() {
  std::int64_t oldest_source = 0;
  std::uint64_t oldest_use = UINT64_MAX;
  map_.for_each([&](std::int64_t source, const Entry& e) {
    if (e.last_use < oldest_use) {
      oldest_use = e.last_use;
      oldest_source = source;
    }
  });
  map_.erase(oldest_source);
}

}  // namespace rigid::loop
