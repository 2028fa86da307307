// What the fault tests share: one rigidd on one bus with a prefix of its own (restartable under the
// same prefix), a monitoring client on that bus and prefix, the bus options the tools need to join
// them, and bounded polling. Processes are tests/rigidd's RigiddProcess: each in its own process
// group, stopped by PID, killed with its group when the test ends, even on failure.
#pragma once

#include <gtest/gtest.h>

#include <chrono>
#include <functional>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "bus_client.hpp"
#include "rigidd_process.hpp"

namespace rigid::faults::testing {

using namespace std::chrono_literals;
using rigid::Bus;
using rigidd::testing::BusClient;
using rigidd::testing::Completed;
using rigidd::testing::RigiddProcess;

// The scenes the fault tests run on. Every body model under gravity (config/scenes/mixed.pbtxt,
// the former default scene):
inline const std::string kDefault = std::string(RIGID_SCENES_DIR) + "/mixed.pbtxt";
inline const std::string kAttitude = std::string(RIGID_SCENES_DIR) + "/attitude.pbtxt";

inline std::string bus_name(Bus b) {
  return b == Bus::kDds ? "dds" : "lcm";
}

inline std::string param_name(const ::testing::TestParamInfo<Bus>& info) {
  return info.param == Bus::kDds ? "Dds" : "Lcm";
}

inline std::vector<std::string> concat(std::vector<std::string> a,
                                       const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

// Polls `done` every 10 ms until it holds or `patience` runs out.
inline bool poll_until(const std::function<bool()>& done, std::chrono::milliseconds patience) {
  const auto deadline = std::chrono::steady_clock::now() + patience;
  while (!done()) {
    if (std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(10ms);
  }
  return true;
}

class Rig {
 public:
  // Starts rigidd on `scene` (realtime) with `extra` arguments, and the monitor.
  Rig(Bus bus, const std::string& scene, const std::vector<std::string>& extra = {})
      : bus_(bus), prefix_(rigidd::testing::unique_prefix("fault")) {
    start_daemon(scene, extra);
    monitor.emplace(bus, prefix_);
  }
  ~Rig() {
    monitor.reset();
    daemon.reset();  // kills its process group if still running
  }
  Rig(const Rig&) = delete;
  Rig& operator=(const Rig&) = delete;

  // (Re)starts rigidd under the same prefix (the previous one must have exited).
  void start_daemon(const std::string& scene, const std::vector<std::string>& extra = {}) {
    daemon.reset();
    daemon.emplace(
        concat({"--scene", scene, "--transport", bus_name(bus_), "--prefix", prefix_}, extra));
  }
  // Until the current rigidd answers a harmless request (set_rtf 1): from then on commands from
  // the monitor reach it.
  bool handshake() {
    rigid::ControlCommand c;
    c.command = rigid::ControlKind::kSetRtf;
    c.rtf = 1.0;
    return monitor->handshake(c, 10s).has_value();
  }
  // The first Stats published after tick `after`, within `patience`.
  std::optional<rigid::StatsReport> stats_after(std::int64_t after,
                                                std::chrono::milliseconds patience = 3s) {
    std::optional<rigid::StatsReport> s;
    monitor->wait(
        [&] {
          if (monitor->stats_locked() && monitor->stats_locked()->tick > after) {
            s = monitor->stats_locked();
          }
          return s.has_value();
        },
        patience);
    return s;
  }
  std::vector<std::string> bus_args() const {
    return {"--transport", bus_name(bus_), "--prefix", prefix_};
  }
  // A client tool run to completion against this rigidd.
  Completed run(const std::string& program, const std::vector<std::string>& args,
                std::chrono::milliseconds patience = 10s) const {
    return rigidd::testing::run_program_to_exit(program, concat(args, bus_args()), patience);
  }
  Bus bus() const { return bus_; }
  const std::string& prefix() const { return prefix_; }

  std::optional<RigiddProcess> daemon;
  std::optional<BusClient> monitor;

 private:
  Bus bus_;
  std::string prefix_;
};

}  // namespace rigid::faults::testing
