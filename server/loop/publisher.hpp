// Sends what the loop produces on one bus, from its own thread, so that a slow or stalled bus or
// subscriber never delays a tick: the loop copies each state into a triple buffer (the publisher
// sends the newest one and the ones it had no time for are counted as skipped) and queues control
// replies; the publisher wakes on a futex. One publisher per transport, so one bus never waits
// for the other.
#pragma once

#include <atomic>
#include <cstdint>
#include <thread>

#include "loop/bounded_queue.hpp"
#include "loop/command.hpp"
#include "loop/doorbell.hpp"
#include "loop/histogram.hpp"
#include "loop/log.hpp"
#include "loop/triple_buffer.hpp"
#include "transport/transport.hpp"

namespace rigid::loop {

class Publisher {
 public:
  // `shape`: a frame with the final number of bodies, so the buffers never grow.
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

  // Loop thread: a new state (copied; allocation-free once the buffers have the frame's shape).
  // command_arrival_ns: see LoopOutput::offer_state.
  void offer(const rigid::StateFrame& frame, std::int64_t command_arrival_ns = 0);
  // Loop thread: the same, by swapping `frame` with the buffer it would be copied into: `frame`
  // comes back with the shape this publisher was made with and stale values. It must have that
  // shape too (the loop's frames all do).
  void hand_over(rigid::StateFrame& frame, std::int64_t command_arrival_ns = 0);
  // Loop thread: waits until the publisher has taken the last state offered (it is being sent or
  // was sent) or until `deadline_ns` (CLOCK_MONOTONIC); true if taken. Allocates nothing.
  bool wait_taken(std::int64_t deadline_ns);
  // Any thread: queues a reply; false (and counted) if the reply queue is full.
  bool reply(const Reply& reply);

  std::int64_t states_sent() const { return states_sent_.load(std::memory_order_relaxed); }
  std::int64_t states_skipped() const { return states_skipped_.load(std::memory_order_relaxed); }
  std::int64_t replies_dropped() const { return replies_dropped_.load(std::memory_order_relaxed); }
  // From a command's arrival to the moment the first state showing it was handed to the bus
  // (publish returned). Read after stop().
  const Histogram& command_to_state() const { return command_to_state_; }

 private:
  void run();
  void wake();
  void send_replies();
  // offer and hand_over once the back buffer holds the new frame.
  void publish_back(std::int64_t command_arrival_ns);

  transport::Transport& transport_;
  Log& log_;
  struct Snapshot {
    rigid::StateFrame frame;
    std::int64_t command_arrival_ns = 0;
  };
  TripleBuffer<Snapshot> states_;
  Histogram command_to_state_;           // publisher thread
  std::int64_t carried_arrival_ns_ = 0;  // loop thread: from a skipped snapshot
  BoundedQueue<Reply> replies_;
  Doorbell taken_;                      // rung by the publisher thread whenever it takes a state
  std::atomic<std::uint32_t> work_{0};  // bumped for every piece of work; the thread waits on it
  std::atomic<bool> stop_{false};
  std::atomic<std::int64_t> states_sent_{0};
  std::atomic<std::int64_t> states_skipped_{0};
  std::atomic<std::int64_t> replies_dropped_{0};
  bool logged_send_failure_ = false;  // publisher thread only
  std::thread thread_;
};

}  // namespace rigid::loop
