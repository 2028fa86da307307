// Names a thread, as top -H, ps -L, perf and /proc/PID/task/TID/comm show it. rigid's
// threads are named "rigid-<role>" (rigid-loop, rigid-pub-dds, rigid-step-1, ...) so that a
// profile or a per-thread CPU reading (bench/loop/loop_bench.cpp) says which one does what: the loop
// and its publishers share one CPU at real-time priority, and which of them takes how much of it
// decides whether ticks are late. Header-only, so that every library may use it without a link.
#pragma once

#include <pthread.h>

#include <algorithm>
#include <cstddef>
#include <string_view>
#include <thread>

namespace rigid::util {

// Linux keeps 15 bytes of a thread's name (and refuses a longer one): a longer `name` is cut.
inline constexpr std::size_t kMaxThreadName = 15;

// Called by the thread that started `t`, right after: the name is in place when the call returns
// (a thread naming itself would do it at some later moment).
inline void name_thread(std::thread& t, std::string_view name) {
  char buf[kMaxThreadName + 1] = {};
  const std::size_t n = std::min(name.size(), kMaxThreadName);
  std::copy_n(name.data(), n, buf);
  // Only a name longer than 15 bytes can fail, and a nameless thread still works: no error path.
  (void)pthread_setname_np(t.native_handle(), buf);
}

}  // namespace rigid::util
