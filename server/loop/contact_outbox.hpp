// The contact events the loop hands to one bus's publisher: a single-producer single-consumer
// queue of ticks' events, fixed in size when it is made, so that the loop puts a tick's events in
// without allocating and without waiting, and the publisher takes them in order on its own thread.
//
// Unlike a state, which the next one replaces, every event counts (an impact is not repeated): a
// tick's events are queued, not overwritten, and a tick that finds no room is dropped whole and
// counted (the publisher adds the count to the next message's `dropped`, so subscribers learn of
// it). The room: kTicks ticks and kEvents events (two full ticks of the physics' 4096), so that a
// publisher a few ticks behind loses nothing; at ~100 B an event that is 0.8 MB a bus, made only
// for scenes with static parts.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "rigid/messages.hpp"

namespace rigid::loop {

class ContactOutbox {
 public:
  static constexpr std::size_t kTicks = 256;
  static constexpr std::size_t kEvents = 2 * rigid::kMaxContactEvents;

  ContactOutbox(std::size_t ticks = kTicks, std::size_t events = kEvents);
  ContactOutbox(const ContactOutbox&) = delete;
  ContactOutbox& operator=(const ContactOutbox&) = delete;

  // Producer: room for one more tick of `events` events now.
  bool has_room(std::size_t events) const;
  // Producer: queues `in` (its tick, sim_time, dropped and events) with `stamp_ns`; false if there
  // is no room (nothing is queued: the caller counts the loss). More than the room for events in
  // all is never queued. Allocates nothing.
  bool put(const rigid::ContactEvents& in, std::int64_t stamp_ns);
  // Consumer: the oldest tick queued, into `out` (its vectors resized, keeping their capacity);
  // false if none.
  bool take(rigid::ContactEvents& out);

  std::size_t tick_capacity() const { return ticks_.size(); }
  std::size_t event_capacity() const { return rows_.size(); }

 private:
  struct Tick {
    std::int64_t tick = 0;
    double sim_time = 0.0;
    std::int64_t stamp_ns = 0;
    std::int64_t dropped = 0;
    std::uint64_t first = 0;  // its first event's position in the event stream
    std::uint32_t count = 0;
  };
  struct Row {
    rigid::ContactKind kind = rigid::ContactKind::kImpact;
    std::int32_t body = 0;
    std::int32_t part = 0;
    double time = 0.0;
    double position[3] = {};
    double normal[3] = {};
    double impulse[3] = {};
  };

  std::vector<Tick> ticks_;
  std::vector<Row> rows_;
  // Positions in the tick and event streams, counted from 0 forever: slot = position % capacity.
  // The producer writes the heads, the consumer the tails.
  std::atomic<std::uint64_t> tick_head_{0};
  std::atomic<std::uint64_t> tick_tail_{0};
  std::atomic<std::uint64_t> event_head_{0};
  std::atomic<std::uint64_t> event_tail_{0};
};

}  // namespace rigid::loop
