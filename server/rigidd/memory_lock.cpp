#include "rigidd/memory_lock.hpp"

#include <sys/mman.h>
#include <sys/resource.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>

namespace rigid::rigidd {
namespace {

// VmLck of /proc/self/status (the size of the locked mappings), in kB; 0 if not found.
long locked_kib() {
  std::ifstream in("/proc/self/status");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("VmLck:", 0) == 0) return std::atol(line.c_str() + 6);
  return 0;
}

}  // namespace

std::string lock_memory() {
  const auto t0 = std::chrono::steady_clock::now();
  if (mlockall(MCL_CURRENT | MCL_ONFAULT) != 0) {
    const int error = errno;
    rlimit limit{};
    std::string allowed = "?";
    if (getrlimit(RLIMIT_MEMLOCK, &limit) == 0) {
      allowed = limit.rlim_cur == RLIM_INFINITY ? std::string("unlimited")
                                                : std::to_string(limit.rlim_cur / 1024) + " KiB";
    }
    return std::string("memory: not locked (mlockall: ") + std::strerror(error) +
           "; RLIMIT_MEMLOCK " + allowed +
           "): a page the kernel drops is read back from disk when next touched, stopping the "
           "thread that touches it; give rigidd CAP_IPC_LOCK or LimitMEMLOCK=infinity";
  }
  // The sanitizers' runtimes answer mlockall with success and lock nothing.
  if (locked_kib() <= 0) {
    return "memory: not locked (mlockall returned without locking anything, as it does in a "
           "sanitizer build)";
  }
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  char took[32];
  std::snprintf(took, sizeof took, "%.1f", ms);
  return std::string("memory: locked in RAM, each page once it is touched (mlockall took ") + took +
         " ms)";
}

}  // namespace rigid::rigidd
