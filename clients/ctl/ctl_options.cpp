#include "ctl/ctl_options.hpp"

#include <algorithm>
#include <array>
#include <utility>

namespace rigid::ctl {
namespace {

using clients::quoted;
using clients::UsageError;

constexpr std::array<std::pair<std::string_view, Command>, 9> kCommands{{
    {"bodies", Command::kBodies},
    {"echo", Command::kEcho},
    {"stats", Command::kStats},
    {"pause", Command::kPause},
    {"resume", Command::kResume},
    {"step", Command::kStep},
    {"reset", Command::kReset},
    {"rate", Command::kRate},
    {"push", Command::kPush},
}};

constexpr std::array<std::string_view, 4> kFlags{"--help", "-h", "--csv", "--once"};

std::string command_names() {
  std::string names;
  for (const auto& [name, command] : kCommands)
    names += (names.empty() ? "" : ", ") + std::string(name);
  return names;
}

// Options each command takes besides the bus options and --timeout.
bool takes(Command c, std::string_view option) {
  switch (c) {
    case Command::kEcho:
      return option == "--rate" || option == "--csv" || option == "--count";
    case Command::kStats:
      return option == "--once" || option == "--count";
    case Command::kPush:
      return option == "--force" || option == "--torque" || option == "--at" ||
             option == "--frame" || option == "--for";
    default:
      return false;
  }
}

std::string_view name_of(Command c) {
  for (const auto& [name, command] : kCommands)
    if (command == c) return name;
  return "?";
}

}  // namespace

CtlOptions parse_options(std::span<const std::string_view> args) {
  CtlOptions o;
  clients::ArgReader reader(args, kFlags);
  std::optional<Command> command;
  std::vector<std::string_view> positional;
  bool have_force = false, have_torque = false;
  std::vector<std::pair<std::string_view, std::string_view>> options;
  while (const auto arg = reader.next()) {
    if (arg->name == "--help" || arg->name == "-h") {
      o.help = true;
      continue;
    }
    if (arg->name.empty()) {
      if (!command) {
        const auto it = std::find_if(kCommands.begin(), kCommands.end(),
                                     [&](const auto& c) { return c.first == arg->value; });
        if (it == kCommands.end()) {
          throw UsageError("unknown command " + quoted(arg->value) +
                           " (commands: " + command_names() + ")");
        }
        command = it->second;
      } else {
        positional.push_back(arg->value);
      }
      continue;
    }
    if (clients::parse_bus_option(*arg, o.bus)) continue;
    if (arg->name == "--timeout") {
      o.timeout = clients::parse_seconds(arg->name, arg->value);
      continue;
    }
    options.emplace_back(arg->name, arg->value);
  }
  if (o.help) return o;
  if (!command) throw UsageError("missing the command (" + command_names() + "; see --help)");
  o.command = *command;

  for (const auto& [name, value] : options) {
    if (!takes(o.command, name)) {
      throw UsageError("unknown option " + quoted(name) + " for " +
                       std::string(name_of(o.command)) + " (see --help)");
    }
    if (name == "--rate") {
      o.rate_hz = clients::parse_positive(name, value, "a rate in Hz > 0");
    } else if (name == "--csv") {
      o.csv = true;
    } else if (name == "--count") {
      o.count = clients::parse_count(name, value);
    } else if (name == "--once") {
      o.once = true;
    } else if (name == "--force") {
      o.force = clients::parse_vec3(name, value);
      have_force = true;
    } else if (name == "--torque") {
      o.torque = clients::parse_vec3(name, value);
      have_torque = true;
    } else if (name == "--at") {
      o.point = clients::parse_vec3(name, value);
    } else if (name == "--frame") {
      if (value == "world") {
        o.frame = rigid::Frame::kWorld;
      } else if (value == "body") {
        o.frame = rigid::Frame::kBody;
      } else {
        throw UsageError("--frame: expected body or world, got " + quoted(value));
      }
    } else if (name == "--for") {
      o.for_seconds = clients::parse_positive(name, value, "a duration in seconds >= 0", true);
    }
  }

  const auto expect_positional = [&](std::size_t n, const char* what) {
    if (positional.size() < n) {
      throw UsageError(std::string(name_of(o.command)) + ": missing " + what + " (see --help)");
    }
    if (positional.size() > n) {
      throw UsageError(std::string(name_of(o.command)) + ": unexpected argument " +
                       quoted(positional[n]));
    }
  };
  switch (o.command) {
    case Command::kEcho:
      o.bodies.assign(positional.begin(), positional.end());
      break;
    case Command::kStep:
      expect_positional(1, "the number of ticks");
      o.steps = clients::parse_count("step", positional[0]);
      break;
    case Command::kRate:
      expect_positional(1, "the real-time factor");
      o.rtf = clients::parse_positive("rate", positional[0], "a real-time factor > 0 and <= 1000");
      if (o.rtf > 1000.0) {
        throw UsageError("rate: expected a real-time factor > 0 and <= 1000, got " +
                         quoted(positional[0]));
      }
      break;
    case Command::kPush:
      expect_positional(1, "the body (a name or an id)");
      o.body = std::string(positional[0]);
      if (!have_force && !have_torque) {
        throw UsageError("push: missing --force fx,fy,fz or --torque tx,ty,tz");
      }
      break;
    default:
      expect_positional(0, "");
      break;
  }
  return o;
}

std::string usage() {
  std::string text =
      R"(Usage: rigidctl COMMAND [ARGS] [--transport dds|lcm] [--prefix P] [--dds-domain N]
                [--lcm-url URL] [--timeout S]

Talks to a running rigidd on one bus.

Commands:
  bodies                  the scene: bodies (id, name, mass, inertia, shape), rate, integrator
  echo [BODY...]          a live table of the bodies' state (all bodies, or those named)
      --rate HZ           refresh rate (default 10; with --csv: every state)
      --csv               CSV lines instead: t,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz
      --count N           stop after N tables (or N states with --csv)
  stats                   live loop statistics, once a second
      --once              print one report and exit
      --count N           stop after N reports
  pause | resume          stop or restart the loop's ticks
  step N                  N ticks, then stay paused (the loop must be paused)
  reset                   back to the scene's initial state at tick 0, wrenches cleared
  rate X                  real-time factor X (realtime mode), 0 < X <= 1000
  push BODY [--force FX,FY,FZ] [--at PX,PY,PZ] [--torque TX,TY,TZ] [--frame body|world]
       [--for S]          a force on BODY (name or id) at a point from its centre of mass, in
                          the body frame (default: the centre of mass), and/or a torque; both
                          are in the world frame unless --frame body. It acts for S seconds of
                          sim time (default 1 s, or the scene's max_ttl if less; 0: one tick);
                          rigidctl waits until rigidd has accepted it and prints the impulse

Options:
)";
  text += clients::bus_options_help();
  text += R"(  --timeout S        how long to wait for rigidd's answer (default 5)
  -h, --help         show this help

Control commands (pause, resume, step, reset, rate) wait for rigidd's reply and print it; push
waits for rigidd to accept the wrench (it says so on rigid/accepted).
Exit status: 0 done; 1 refused: by rigidd, or by rigidctl before sending for what rigidd would
refuse (a body the scene lacks, a force, torque or --for above the scene's limits), or a bus could
not be set up; 2 a bad command line (what the command line alone shows); 3 no answer from rigidd
within the timeout.
)";
  return text;
}

}  // namespace rigid::ctl
