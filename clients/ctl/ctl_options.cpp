#include "ctl/ctl_options.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <utility>

namespace rigid::ctl {
namespace {

using clients::quoted;
using clients::UsageError;

constexpr std::array<std::pair<std::string_view, Command>, 10> kCommands{{
    {"bodies", Command::kBodies},
    {"echo", Command::kEcho},
    {"stats", Command::kStats},
    {"pause", Command::kPause},
    {"resume", Command::kResume},
    {"step", Command::kStep},
    {"reset", Command::kReset},
    {"rate", Command::kRate},
    {"push", Command::kPush},
    {"set", Command::kSet},
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
    case Command::kSet:
      return option == "--position" || option == "--orientation" || option == "--rpy" ||
             option == "--velocity" || option == "--angular-velocity" || option == "--frame";
    default:
      return false;
  }
}

std::string_view name_of(Command c) {
  for (const auto& [name, command] : kCommands)
    if (command == c) return name;
  return "?";
}

// w,x,y,z within 1e-3 of unit length (rigidd's tolerance; it normalises).
std::array<double, 4> parse_orientation(std::string_view option, std::string_view text) {
  std::array<double, 4> q{};
  std::string_view rest = text;
  for (std::size_t i = 0; i < 4; ++i) {
    const std::size_t comma = rest.find(',');
    if ((i < 3) == (comma == std::string_view::npos)) {
      throw UsageError(std::string(option) + ": expected four numbers w,x,y,z, got " +
                       quoted(text));
    }
    q[i] = clients::parse_double(option, rest.substr(0, comma), "four numbers w,x,y,z");
    if (comma != std::string_view::npos) rest = rest.substr(comma + 1);
  }
  const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (!(std::abs(n - 1.0) <= 1e-3)) {
    throw UsageError(std::string(option) + ": expected a unit quaternion w,x,y,z (|q| = 1 within " +
                     "1e-3), got " + quoted(text));
  }
  return q;
}

// Roll, pitch, yaw in degrees (as rigid-attitude's --target-rpy): R = Rz(yaw) Ry(pitch) Rx(roll).
std::array<double, 4> orientation_of_rpy(const rigid::Vec3& rpy_deg) {
  const double k = std::numbers::pi / 360.0;  // half the angle, in radians
  const double cr = std::cos(rpy_deg[0] * k), sr = std::sin(rpy_deg[0] * k);
  const double cp = std::cos(rpy_deg[1] * k), sp = std::sin(rpy_deg[1] * k);
  const double cy = std::cos(rpy_deg[2] * k), sy = std::sin(rpy_deg[2] * k);
  return {cy * cp * cr + sy * sp * sr, cy * cp * sr - sy * sp * cr, cy * sp * cr + sy * cp * sr,
          sy * cp * cr - cy * sp * sr};
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
    } else if (name == "--position") {
      o.position = clients::parse_vec3(name, value);
    } else if (name == "--orientation" || name == "--rpy") {
      if (o.orientation)
        throw UsageError("set: give the orientation once (--orientation or --rpy)");
      o.orientation = name == "--rpy" ? orientation_of_rpy(clients::parse_vec3(name, value))
                                      : parse_orientation(name, value);
    } else if (name == "--velocity") {
      o.velocity = clients::parse_vec3(name, value);
    } else if (name == "--angular-velocity") {
      o.angular_velocity = clients::parse_vec3(name, value);
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
    case Command::kSet:
      expect_positional(1, "the body (a name or an id)");
      o.body = std::string(positional[0]);
      if (!o.position && !o.orientation && !o.velocity && !o.angular_velocity) {
        throw UsageError(
            "set: nothing to set (--position, --orientation or --rpy, --velocity, "
            "--angular-velocity)");
      }
      break;
    case Command::kReset:
      if (positional.size() > 1) {
        throw UsageError("reset: unexpected argument " + quoted(positional[1]));
      }
      if (!positional.empty()) o.body = std::string(positional[0]);
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
  reset [BODY]            back to the scene's initial state at tick 0, wrenches cleared; with
                          BODY (name or id), that body alone back to its scene state, the
                          wrenches on it dropped (the tick goes on)
  rate X                  real-time factor X (realtime mode), 0 < X <= 1000
  push BODY [--force FX,FY,FZ] [--at PX,PY,PZ] [--torque TX,TY,TZ] [--frame body|world]
       [--for S]          a force on BODY (name or id) at a point from its centre of mass, in
                          the body frame (default: the centre of mass), and/or a torque; both
                          are in the world frame unless --frame body. It acts for S seconds of
                          sim time (default 1 s, or the scene's max_ttl if less; 0: one tick);
                          rigidctl waits until rigidd has accepted it and prints the impulse
  set BODY [--position X,Y,Z] [--orientation W,X,Y,Z | --rpy R,P,Y] [--velocity VX,VY,VZ]
      [--angular-velocity WX,WY,WZ] [--frame body|world]
                          sets those parts of BODY's state (the others keep theirs) between two
                          ticks: the position of its centre of mass in the world frame, its
                          orientation (a unit quaternion, or roll, pitch, yaw in degrees: Rz Ry Rx),
                          its velocity and angular velocity in the world frame, or with --frame
                          body in the body's frame as oriented after the edit

Options:
)";
  text += clients::bus_options_help();
  text += R"(  --timeout S        how long to wait for rigidd's answer (default 5)
  -h, --help         show this help

Control commands (pause, resume, step, reset, rate) and edits (set, reset BODY) wait for rigidd's
reply and print it with the tick it took effect at; push waits for rigidd to accept the wrench
(it says so on rigid/accepted).
Exit status: 0 done; 1 refused: by rigidd, or by rigidctl before sending for what rigidd would
refuse (a body the scene lacks, a force, torque or --for above the scene's limits), or a bus could
not be set up; 2 a bad command line (what the command line alone shows); 3 no answer from rigidd
within the timeout.
)";
  return text;
}

}  // namespace rigid::ctl
