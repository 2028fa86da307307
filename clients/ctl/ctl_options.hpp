// rigidctl's command line: a command and its arguments, the bus options, and their checks (every
// error is one line naming the argument and its value; rigidctl then exits with status 2). What
// needs the running scene (a body's name, the scene's limits) is checked later, against it.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "cli/cli.hpp"

namespace rigid::ctl {

enum class Command {
  kBodies,
  kEcho,
  kStats,
  kPause,
  kResume,
  kStep,
  kReset,
  kRate,
  kPush,
  kSet,
};

struct CtlOptions {
  Command command = Command::kBodies;
  client::BusOptions bus;
  std::chrono::milliseconds timeout{5000};  // for an answer from rigidd
  bool help = false;

  // echo
  std::vector<std::string> bodies;  // empty: all
  std::optional<double> rate_hz;  // display rate; default 10 Hz for the table, every state for CSV
  bool csv = false;
  std::optional<std::int64_t> count;  // stop after this many outputs
  // stats
  bool once = false;
  // step
  std::int64_t steps = 0;
  // rate
  double rtf = 1.0;
  // push
  std::string body;
  rigid::Vec3 force{};
  rigid::Vec3 torque{};
  rigid::Vec3 point{};
  rigid::Frame frame = rigid::Frame::kWorld;  // of the force and the torque; set: the velocities
  std::optional<double> for_seconds;  // ttl (0: one tick); unset: push_request.hpp's default
  // set BODY (body, and frame: of the velocities); reset BODY (body; empty: the whole world)
  std::optional<rigid::Vec3> position;
  std::optional<std::array<double, 4>> orientation;  // w, x, y, z (--orientation or --rpy)
  std::optional<rigid::Vec3> velocity;
  std::optional<rigid::Vec3> angular_velocity;
};

// Parses the arguments after the program name. Throws clients::UsageError.
CtlOptions parse_options(std::span<const std::string_view> args);

std::string usage();

}  // namespace rigid::ctl
