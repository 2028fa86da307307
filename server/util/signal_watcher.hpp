// Signals without a handler or a global flag: the constructor blocks the given signals in the
// calling thread (every thread created afterwards inherits the mask, so none of them is
// interrupted) and opens a signalfd; whoever waits on it (rigidd's main thread) reads them as
// ordinary events. Construct it before any other thread starts.
#pragma once

#include <signal.h>

#include <chrono>
#include <initializer_list>
#include <optional>

namespace rigid::util {

class SignalWatcher {
 public:
  // Throws std::system_error if the signals cannot be blocked or the signalfd opened.
  explicit SignalWatcher(std::initializer_list<int> signals);
  ~SignalWatcher();
  SignalWatcher(const SignalWatcher&) = delete;
  SignalWatcher& operator=(const SignalWatcher&) = delete;

  // The next signal received, or nothing after `timeout`.
  std::optional<int> wait(std::chrono::milliseconds timeout);

 private:
  sigset_t set_;
  sigset_t previous_;
  int fd_ = -1;
};

}  // namespace rigid::util
