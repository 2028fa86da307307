#include "loop/shared_states.hpp"

#include <stdexcept>
#include <string>
#include <utility>

#include "loop/clock.hpp"

namespace rigid::loop {

SharedStates::SharedStates(const rigid::StateFrame& shape) {
  slots_.emplace_back(shape, 0);
}

int SharedStates::add_reader() {
  ++readers_;
  for (Slot& s : slots_)
    s.arrival.push_back(0);
  const rigid::StateFrame& shape = slots_.front().frame;
  slots_.emplace_back(shape, readers_);
  slots_.emplace_back(shape, readers_);
  return readers_ - 1;
}

int SharedStates::free_slot() const {
  // The acquire pairs with release(): the last reader's reads of the slot are done before the
  // writer overwrites it.
  for (int s = 0; s < slots(); ++s)
    if (s != lent_ && at(s).holders.load(std::memory_order_acquire) == 0) return s;
  // Only a reader holding more than two slots (a bug) or a writer sharing with more readers than
  // were added gets here.
  throw std::logic_error("SharedStates: every slot is held (more holders than readers added?)");
}

void SharedStates::check_holders(int holders) const {
  if (holders < 1 || holders > readers_) {
    throw std::logic_error("SharedStates: a state shared with " + std::to_string(holders) +
                           " readers, " + std::to_string(readers_) + " added");
  }
}

void SharedStates::share(int slot, int holders) {
  at(slot).frame.stamp_ns = realtime_ns();
  // Relaxed is enough: a reader gets the slot through its mailbox, whose release orders this and
  // the frame's contents before its acquire.
  at(slot).holders.store(holders, std::memory_order_relaxed);
}

int SharedStates::put_swapped(rigid::StateFrame& frame, int holders) {
  check_holders(holders);
  const int s = free_slot();
  std::swap(at(s).frame, frame);  // swaps the vectors' buffers: no copy, no allocation
  share(s, holders);
  return s;
}

int SharedStates::put_copied(const rigid::StateFrame& frame, int holders) {
  check_holders(holders);
  const int s = free_slot();
  at(s).frame = frame;  // same shape: the vectors keep their storage
  share(s, holders);
  return s;
}

rigid::StateFrame& SharedStates::lend() {
  if (lent_ < 0) lent_ = free_slot();
  return at(lent_).frame;
}

int SharedStates::put_lent(int holders) {
  if (lent_ < 0) throw std::logic_error("SharedStates: put_lent without lend");
  check_holders(holders);
  const int s = lent_;
  lent_ = -1;
  share(s, holders);
  return s;
}

void SharedStates::release(int slot) {
  at(slot).holders.fetch_sub(1, std::memory_order_acq_rel);
}

}  // namespace rigid::loop
