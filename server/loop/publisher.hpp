// Sends what the loop produces on one bus, from its own thread, so that a slow or stalled bus or
// subscriber never delays a tick: the loop puts each state into a slot that every bus's
// publisher reads (SharedStates: no copy per bus) and offers it through the publisher's mailbox,
// which holds the newest state not yet taken (one it replaces before it was taken is counted as
// skipped); replies are queued, and so are contact events (ContactOutbox: every tick's, none
// replaced; a tick without room is dropped and counted, and the count goes out in the next
// message's `dropped`). The publisher sends the contact events first, then the state, then the
// replies. It wakes on a futex. One publisher per transport, so one bus never waits for the
// other.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <thread>

#include "loop/bounded_queue.hpp"
#include "loop/command.hpp"
#include "loop/contact_outbox.hpp"
#include "loop/doorbell.hpp"
#include "loop/histogram.hpp"
#include "loop/log.hpp"
#include "loop/realtime_share.hpp"
#include "loop/shared_states.hpp"
#include "transport/transport.hpp"

namespace rigid::loop {

class Publisher {
 public:
  // Reads the states of `states` (shared with the other buses' publishers; it becomes one of its
  // readers), which must outlive it. contacts: make a ContactOutbox (a world with static parts).
  Publisher(transport::Transport& transport, SharedStates& states, Log& log,
            std::size_t reply_capacity = 256, bool contacts = false);
  // Alone: its own states, shaped like `shape` (the final number of bodies, so nothing grows).
  Publisher(transport::Transport& transport, const rigid::StateFrame& shape, Log& log,
            std::size_t reply_capacity = 256);
  ~Publisher();
  Publisher(const Publisher&) = delete;
  Publisher& operator=(const Publisher&) = delete;

  rigid::Bus bus() const { return transport_.bus(); }
  transport::Transport& transport() { return transport_; }

  void start();
  std::thread::native_handle_type native_handle() { return thread_.native_handle(); }
  // Sends what is pending, then stops the thread. Idempotent.
  void stop();

  // Loop thread: slot `slot` of its SharedStates, put there for this publisher among others (its
  // holders count this one), to send. command_arrival_ns: see LoopOutput::offer_state.
  // Allocates nothing.
  void offer_slot(int slot, std::int64_t command_arrival_ns = 0);
  // Loop thread, a publisher alone (its SharedStates has no other reader): a new state, copied
  // into a free slot (allocation-free once the slots have the frame's shape).
  void offer(const rigid::StateFrame& frame, std::int64_t command_arrival_ns = 0);
  // Loop thread, alone: the same, by swapping `frame` with the slot's: `frame` comes back with the
  // shape this publisher was made with and stale values. It must have that shape too.
  void hand_over(rigid::StateFrame& frame, std::int64_t command_arrival_ns = 0);
  // Loop thread: waits until the publisher has taken the last state offered (it is being sent or
  // was sent) or until `deadline_ns` (CLOCK_MONOTONIC); true if taken. Allocates nothing.
  bool wait_taken(std::int64_t deadline_ns);
  // Any thread: queues a reply; false (and counted) if the reply queue is full.
  bool reply(const Reply& reply);
  // Loop thread: queues a tick's contact events, stamped stamp_ns; false if there was no room
  // (or no outbox): they are then dropped and counted. Allocates nothing.
  bool offer_contacts(const rigid::ContactEvents& events, std::int64_t stamp_ns);
  // Loop thread: waits until there is room for a tick of `events` events, or until `deadline_ns`;
  // true if there is (always, without an outbox: there is nothing to wait for).
  bool wait_contacts_room(std::size_t events, std::int64_t deadline_ns);
  // Says that the publisher's thread was just put at SCHED_FIFO `priority` (Server). From then on
  // the thread steps down to normal priority while it takes more than kRealtimeLimit of a CPU over
  // a second, and back up once it takes less than kRealtimeResume (realtime_share.hpp: a
  // publisher of a large world would otherwise leave the loop's CPU no time for its other threads,
  // and the kernel would stop the loop to give them some). Each change is logged.
  static constexpr double kRealtimeLimit = 0.25;
  static constexpr double kRealtimeResume = 0.10;
  void watch_realtime_share(int priority);
  // How often the thread stepped down to normal priority so far.
  std::int64_t priority_step_downs() const {
    return priority_step_downs_.load(std::memory_order_relaxed);
  }

  std::int64_t states_sent() const { return states_sent_.load(std::memory_order_relaxed); }
  std::int64_t states_skipped() const { return states_skipped_.load(std::memory_order_relaxed); }
  std::int64_t replies_dropped() const { return replies_dropped_.load(std::memory_order_relaxed); }
  // Contact events: messages sent, and events this bus lost (no room, or the bus refused them).
  std::int64_t contacts_sent() const { return contacts_sent_.load(std::memory_order_relaxed); }
  std::int64_t contact_events_lost() const {
    return contact_events_lost_.load(std::memory_order_relaxed);
  }
  // From a command's arrival to the moment the first state showing it was handed to the bus
  // (publish returned). Read after stop().
  const Histogram& command_to_state() const { return command_to_state_; }

 private:
  void run();
  void wake();
  void send_replies();
  // Publisher thread: the realtime share's window (watch_realtime_share), and its changes.
  void mind_realtime_share(int priority);
  // Publisher thread: sends the state in the mailbox, if any.
  void send_state();
  // Publisher thread: sends every tick of contact events queued.
  void send_contacts();

  // The mailbox: the slot offered and not yet taken (with kFresh), or an old slot (without).
  static constexpr std::uint32_t kFresh = 1u << 31;

  transport::Transport& transport_;
  Log& log_;
  std::unique_ptr<SharedStates> own_states_;  // alone: its own (else null)
  SharedStates& states_;
  const int reader_;  // its index among states_'s readers
  std::atomic<std::uint32_t> mailbox_{0};
  Histogram command_to_state_;           // publisher thread
  std::int64_t carried_arrival_ns_ = 0;  // loop thread: from a skipped state
  BoundedQueue<Reply> replies_;
  Doorbell taken_;                      // rung by the publisher thread whenever it takes a state
  std::atomic<std::uint32_t> work_{0};  // bumped for every piece of work; the thread waits on it
  std::atomic<bool> stop_{false};
  std::atomic<std::int64_t> states_sent_{0};
  std::atomic<std::int64_t> states_skipped_{0};
  std::atomic<std::int64_t> replies_dropped_{0};
  std::unique_ptr<ContactOutbox> contacts_;  // null: no static parts, no contact events
  rigid::ContactEvents contact_message_;     // publisher thread: the message sent, reused
  std::atomic<std::int64_t> contacts_sent_{0};
  std::atomic<std::int64_t> contact_events_lost_{0};
  bool logged_send_failure_ = false;     // publisher thread only
  bool logged_contact_failure_ = false;  // publisher thread only
  // Edits' answers logged this second, and those left out (a client may edit every tick): at
  // most kEditLinesPerSecond lines a second, then one line counting the rest. Its thread only.
  static constexpr int kEditLinesPerSecond = 10;
  std::int64_t edit_window_ns_ = 0;
  int edit_lines_ = 0;
  std::int64_t edit_lines_left_out_ = 0;
  std::atomic<int> realtime_priority_{0};  // 0: not at real-time priority
  RealtimeShare realtime_share_{kRealtimeLimit, kRealtimeResume, 1'000'000'000};  // its thread
  int priority_changes_logged_ = 0;                                               // its thread
  std::atomic<std::int64_t> priority_step_downs_{0};
  std::thread thread_;
};

}  // namespace rigid::loop
