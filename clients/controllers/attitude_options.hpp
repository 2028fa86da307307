// rigid-attitude's command line (every error is one line naming the argument and its value; the
// program then exits with status 2).
#pragma once

#include <chrono>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "cli/cli.hpp"

namespace rigid::controllers {

struct AttitudeOptions {
  std::string body;                // empty: the scene's only body
  rigid::Vec3 target_rpy_deg{};    // roll, pitch, yaw of the target (deg)
  double max_thrust = 5.0;         // N, each thruster
  double rate_hz = 100.0;          // control rate
  std::optional<double> arm;       // m: thruster lever arm for a body that is not a box
  std::optional<double> duration;  // s; unset: until SIGINT/SIGTERM
  double settle_deg = 1.0;         // "settled": within this for settle_hold
  bool exit_when_settled = false;
  client::BusOptions bus;
  std::chrono::milliseconds timeout{5000};  // for rigidd's SceneInfo and states
  bool help = false;
};

AttitudeOptions parse_options(std::span<const std::string_view> args);

std::string usage();

}  // namespace rigid::controllers
