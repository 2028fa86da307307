// The systemd notification protocol (sd_notify), for a Type=notify unit. Outside systemd
// (NOTIFY_SOCKET unset) every call does nothing.
#pragma once

#include <chrono>
#include <optional>
#include <string_view>

namespace rigid::rigidd {

class SystemdNotifier {
 public:
  SystemdNotifier();

  void ready();
  // Only while the loop makes progress: a hung loop stops the pings and systemd restarts us.
  void watchdog();
  void stopping();
  void status(std::string_view text);

  // How often to ping: half the unit's WatchdogSec, or nothing if no watchdog is asked for.
  std::optional<std::chrono::microseconds> watchdog_period() const { return watchdog_period_; }

 private:
  std::optional<std::chrono::microseconds> watchdog_period_;
};

}  // namespace rigid::rigidd
