// Where rigid's real-time threads run: the last CPU this process may use (the first is where
// interrupts and most other work land by default), and pinning a thread to one CPU. rigidd's
// loop and publishers go there (loop/server.cpp), and so does the tick thread of loop_bench's
// stand-in for rigidd (bench/loop/echo_server.cpp), so that both run where the other would.
// Header-only, like thread_name.hpp.
#pragma once

#include <pthread.h>
#include <sched.h>

namespace rigid::util {

// The highest-numbered CPU in this process's affinity mask; -1 if it cannot be read.
inline int last_allowed_cpu() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) != 0) return -1;
  for (int cpu = CPU_SETSIZE - 1; cpu >= 0; --cpu)
    if (CPU_ISSET(cpu, &set)) return cpu;
  return -1;
}

// Pins `thread` to `cpu` alone; whether that worked.
inline bool pin_to_cpu(pthread_t thread, int cpu) {
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(cpu, &set);
  return pthread_setaffinity_np(thread, sizeof set, &set) == 0;
}

}  // namespace rigid::util
