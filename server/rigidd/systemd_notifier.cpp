#include "rigidd/systemd_notifier.hpp"

#include <systemd/sd-daemon.h>

#include <cstdint>
#include <string>

namespace rigid::rigidd {

SystemdNotifier::SystemdNotifier() {
  std::uint64_t usec = 0;
  // > 0: WATCHDOG_USEC is set for this process (and WATCHDOG_PID, if set, is ours).
  if (sd_watchdog_enabled(0, &usec) > 0 && usec > 0) {
    watchdog_period_ = std::chrono::microseconds(usec / 2);
  }
}

void SystemdNotifier::ready() {
  sd_notify(0, "READY=1");
}

void SystemdNotifier::watchdog() {
  sd_notify(0, "WATCHDOG=1");
}

void SystemdNotifier::stopping() {
  sd_notify(0, "STOPPING=1");
}

void SystemdNotifier::status(std::string_view text) {
  const std::string message = "STATUS=" + std::string(text);
  sd_notify(0, message.c_str());
}

}  // namespace rigid::rigidd
