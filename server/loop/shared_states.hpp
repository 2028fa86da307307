// The states the loop hands to its publishers, shared by all of them instead of copied to each.
// A state of 10^4 bodies is 1 MB and of 10^5 bodies 10 MB: a copy per bus would cost the loop's
// thread milliseconds a state (bench/notes/loop-latency.md, "Handing a state to the buses"). Here
// the loop puts a state into a free slot once (by swapping its frame in) and every publisher
// reads that slot; the last one to let go frees it.
//
// Why 2 R + 1 slots for R readers: a reader holds at most two slots at a time, the one offered and
// not yet taken (its mailbox, Publisher) and the one it is sending; the writer drops the reference
// of an offered slot that a newer one replaces before it was taken. So at most 2 R slots are held
// and the writer always finds a free one, without waiting and without allocating. With the two
// buses that is 5 frames, all there is: the loop writes each state straight into a free slot
// (lend, put_lent), and keeps no frame of its own.
//
// Threads: one writer (the loop) takes free slots, fills them (in place: lend, put_lent) and sets
// how many readers hold them; readers only release. Slots and readers are added before any reader's
// thread starts.
#pragma once

#include <atomic>
#include <cstdint>
#include <deque>
#include <vector>

#include "rigid/messages.hpp"

namespace rigid::loop {

class SharedStates {
 public:
  // One slot, a copy of `shape` (the final number of bodies, so that nothing grows later); every
  // add_reader() adds two more.
  explicit SharedStates(const rigid::StateFrame& shape);
  SharedStates(const SharedStates&) = delete;
  SharedStates& operator=(const SharedStates&) = delete;

  // Before any reader runs: room for one more reader (two more slots); returns its index.
  int add_reader();
  int readers() const { return readers_; }
  int slots() const { return static_cast<int>(slots_.size()); }

  // Writer: puts `frame` into a slot no reader holds, by swapping it in (`frame` comes back with
  // the same shape and stale values) or by copying it, stamps it with the wall clock (the moment
  // the state goes to the buses: every bus then carries the same stamp for the same state) and
  // marks it held by `holders` readers, each of which must then be offered it. Returns the slot.
  // Allocates nothing once the slots have the frame's shape.
  int put_swapped(rigid::StateFrame& frame, int holders);
  int put_copied(const rigid::StateFrame& frame, int holders);
  // Writer: a slot no reader holds, whose frame (same shape, stale values) the writer fills in
  // place and then shares with put_lent, as put_swapped shares a frame of its own: so the writer
  // needs no frame of its own (rigidd's loop: one state frame less, 108 MB at 10^6 bodies). The
  // slot stays the writer's until put_lent; lend() again before that gives the same one.
  rigid::StateFrame& lend();
  // Stamps and shares the lent slot as put_swapped does; returns it. std::logic_error if nothing
  // is lent or holders is out of range (the slot then stays lent).
  int put_lent(int holders);

  // A reader's view of a slot it holds (valid until it releases it).
  const rigid::StateFrame& frame(int slot) const { return at(slot).frame; }
  // When the command that first shows in slot's state arrived for `reader` (0 for none): the
  // writer sets it before it offers the slot to that reader, who reads it while holding the slot.
  // Per reader, because a state a reader skipped hands its arrival on to that reader's next one.
  void set_arrival(int slot, int reader, std::int64_t ns) {
    at(slot).arrival[static_cast<std::size_t>(reader)] = ns;
  }
  std::int64_t arrival(int slot, int reader) const {
    return at(slot).arrival[static_cast<std::size_t>(reader)];
  }
  // A reader lets go of a slot, or the writer on behalf of a reader that never took it.
  void release(int slot);
  // Tests: how many readers hold a slot.
  int holders(int slot) const { return at(slot).holders.load(std::memory_order_acquire); }

 private:
  struct Slot {
    Slot(const rigid::StateFrame& shape, int readers)
        : frame(shape), arrival(static_cast<std::size_t>(readers), 0) {}
    rigid::StateFrame frame;
    std::vector<std::int64_t> arrival;  // by reader
    std::atomic<int> holders{0};
  };
  const Slot& at(int slot) const { return slots_[static_cast<std::size_t>(slot)]; }
  Slot& at(int slot) { return slots_[static_cast<std::size_t>(slot)]; }
  // The writer's next slot: a free one (there always is one, see above).
  int free_slot() const;
  // Throws std::logic_error unless 1 <= holders <= readers().
  void check_holders(int holders) const;
  void share(int slot, int holders);

  // A deque, so that adding slots never moves one (a Slot's atomic cannot move).
  std::deque<Slot> slots_;
  int readers_ = 0;
  int lent_ = -1;  // the slot lend() gave and put_lent has not shared yet
};

}  // namespace rigid::loop
