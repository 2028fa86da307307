// Where the loop and the intake hand what must go out on the buses. Implementations (the server's
// publishers, a test's recorder) must return quickly and allocate nothing: they are called on the
// loop thread.
#pragma once

#include <cstdint>

#include "common/journal_entry.hpp"
#include "loop/command.hpp"
#include "rigid/messages.hpp"

namespace rigid::loop {

class ReplySink {
 public:
  virtual ~ReplySink() = default;
  // The answer to a control request, for the bus in reply.bus.
  virtual void reply(const Reply& reply) = 0;
};

class LoopOutput : public ReplySink {
 public:
  // A new state for every bus. The frame is only valid during the call (copy it).
  // command_arrival_ns: when the earliest command that first shows in this state arrived
  // (CLOCK_MONOTONIC), or 0: the publishers measure command-to-state latency with it.
  virtual void offer_state(const rigid::StateFrame& frame, std::int64_t command_arrival_ns) = 0;
  // The same, allowed to take the frame's contents instead of copying them (a state of 10^4
  // bodies is 1 MB; the server shares it among its buses, shared_states.hpp): the frame comes back
  // with the same shape (ids and array sizes) and stale values, which the loop overwrites before
  // its next offer.
  // By default a copy (offer_state).
  virtual void hand_over_state(rigid::StateFrame& frame, std::int64_t command_arrival_ns) {
    offer_state(frame, command_arrival_ns);
  }
  // A frame to write the next state into in place, for a loop configured with
  // LoopConfig::output_lends_frames (the server: a free slot of the frames its buses read,
  // shared_states.hpp), so that the loop keeps no state frame of its own. It has the shape
  // common::shape_state_frame gives and stale values; it goes out with hand_over_lent, the next
  // call. By default none: an output that lends must override both.
  virtual rigid::StateFrame* lend_frame() { return nullptr; }
  virtual void hand_over_lent(std::int64_t /*command_arrival_ns*/) {}
  // Waits until every bus has taken the last state offered, so that the next offer replaces
  // none, or until `deadline_ns` (CLOCK_MONOTONIC); true if taken. The loop calls it before a
  // state that must not be skipped (lockstep, step requests). Allocates nothing. By default
  // (a test's recorder keeps every state) there is nothing to wait for.
  virtual bool wait_states_taken(std::int64_t /*deadline_ns*/) { return true; }
  // The contact events of a tick (tick, sim_time, events, and in `dropped` those the physics
  // could not keep since start), for every bus; only valid during the call (copy them). A bus
  // without room for them drops them and counts them (contact_outbox.hpp). By default dropped.
  virtual void offer_contacts(const rigid::ContactEvents& /*events*/) {}
  // Waits until every bus has room for a tick of `events` events, or until `deadline_ns`
  // (CLOCK_MONOTONIC); true if there is room. The loop calls it before the events of a tick that
  // must not be skipped (lockstep, step requests), as wait_states_taken. Allocates nothing.
  virtual bool wait_contacts_room(std::size_t /*events*/, std::int64_t /*deadline_ns*/) {
    return true;
  }
  // A command carried out, or a published state's hash, in the loop's order (journal_entry.hpp).
  // By default dropped: only the server keeps a journal.
  virtual void journal(const common::JournalEntry& /*entry*/) {}
};

}  // namespace rigid::loop
