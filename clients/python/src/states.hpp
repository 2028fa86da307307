// How rigidd's states reach Python: each state the session receives (one shared, immutable copy)
// goes to every open stream's queue (Client.states(): a Python thread takes it, waiting with the
// GIL released) and to every state callback (Client.on_state(): run on the bus's receive thread
// itself, with the GIL, so no thread has to be woken for it).
//
// Locks, so that no thread waits for the GIL while holding what a thread with the GIL may wait
// for: `queues_mutex_` is held only without Python (queueing), `callbacks_mutex_` is held by the
// receive thread while it runs callbacks and is taken by Python threads only with the GIL
// released.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "common.hpp"
#include "session_api.hpp"

namespace rigid::python {

// Taking the GIL once the interpreter has begun to finalize ends the calling thread inside
// CPython; a receive thread must not try (Client's atexit hook closes sessions before that).
bool finalizing();

// One received state, immutable; its arrays are read-only views of the frame it holds.
class PyState {
 public:
  explicit PyState(std::shared_ptr<const StateFrame> frame);
  const StateFrame& frame() const { return *frame_; }
  py::ssize_t n() const { return static_cast<py::ssize_t>(frame_->body_count()); }
  py::array ids() const;
  py::array positions() const;
  py::array orientations() const;
  py::array velocities() const;
  py::array angular_velocities() const;
  std::string repr() const;

 private:
  std::shared_ptr<const StateFrame> frame_;
  py::capsule owner_;
};

// States for one stream, newest last; bounded: a slow reader loses the oldest (counted).
struct StateQueue {
  std::mutex mutex;
  std::condition_variable changed;
  std::deque<std::shared_ptr<const StateFrame>> frames;
  std::size_t capacity = 1024;
  std::int64_t dropped = 0;
  bool closed = false;
};

// A Python function called with each state (Client.on_state). Its Python objects are touched
// only with the GIL; `active` and `calls` are read by any thread.
struct StateCallback {
  explicit StateCallback(py::function f) : fn(std::move(f)) {}
  ~StateCallback();
  StateCallback(const StateCallback&) = delete;
  StateCallback& operator=(const StateCallback&) = delete;

  py::function fn;
  py::object error = py::none();  // the exception that ended it
  std::atomic<bool> active{true};
  std::atomic<std::int64_t> calls{0};
};

class StateDelivery {
 public:
  // On the receive thread, without the GIL: queue `state` for every stream, then run the
  // callbacks (taking the GIL once for all of them).
  void deliver(const std::shared_ptr<const StateFrame>& state);

  void add_queue(const std::shared_ptr<StateQueue>& q);
  void remove_queue(const std::shared_ptr<StateQueue>& q);

  // With the GIL held. remove_callback returns once the callback is not running and will not
  // run again; called from inside a callback it only marks it (its delivery drops it after),
  // and add_callback there lets the new one join after this delivery.
  void add_callback(const std::shared_ptr<StateCallback>& c);
  void remove_callback(const std::shared_ptr<StateCallback>& c);
  // With the GIL, once no delivery can come any more (the session closed): ends them all.
  void end_callbacks();

  // True on the receive thread while it runs callbacks: a call there must not wait for the bus,
  // whose next message this very thread would have to receive.
  bool in_callback() const { return delivering_.load() == std::this_thread::get_id(); }

 private:
  void run_callbacks(const std::shared_ptr<const StateFrame>& state);

  std::mutex queues_mutex_;
  std::vector<std::shared_ptr<StateQueue>> queues_;
  std::mutex callbacks_mutex_;
  std::vector<std::shared_ptr<StateCallback>> callbacks_;
  std::vector<std::shared_ptr<StateCallback>> added_;  // from inside a callback (same lock)
  std::atomic<bool> any_callback_{false};
  std::atomic<std::thread::id> delivering_{};
};

// Client.states(): an iterator over the states delivered from its creation on.
class PyStateStream {
 public:
  PyStateStream(std::shared_ptr<StateDelivery> delivery, std::size_t capacity, double timeout,
                std::string bus);
  ~PyStateStream() { close(); }
  PyStateStream(const PyStateStream&) = delete;
  PyStateStream& operator=(const PyStateStream&) = delete;

  // The next state; TimeoutError after `timeout` seconds without one. Waits in slices so that
  // Ctrl-C is seen within 0.1 s.
  PyState next();
  void close();
  std::int64_t dropped() const;
  std::size_t pending() const;

 private:
  std::shared_ptr<StateDelivery> delivery_;
  std::shared_ptr<StateQueue> queue_;
  double timeout_;
  std::string bus_;
};

// Client.on_state()'s handle: ends the callback on close() (or leaving a `with` block).
class PyStateCallback {
 public:
  PyStateCallback(std::shared_ptr<StateDelivery> delivery, std::shared_ptr<StateCallback> c)
      : delivery_(std::move(delivery)), callback_(std::move(c)) {}
  void close();
  bool active() const { return callback_->active.load(); }
  std::int64_t calls() const { return callback_->calls.load(); }
  py::object error() const { return callback_->error; }

 private:
  std::weak_ptr<StateDelivery> delivery_;
  std::shared_ptr<StateCallback> callback_;
};

}  // namespace rigid::python
