#include "attitude_options.hpp"

#include <array>

namespace rigid::controllers {

using clients::quoted;
using clients::UsageError;

AttitudeOptions parse_options(std::span<const std::string_view> args) {
  constexpr std::array<std::string_view, 3> kFlags{"--help", "-h", "--exit-when-settled"};
  AttitudeOptions o;
  clients::ArgReader reader(args, kFlags);
  bool have_body = false;
  while (const auto arg = reader.next()) {
    const std::string_view name = arg->name, value = arg->value;
    if (name.empty()) {
      if (have_body) throw UsageError("unexpected argument " + quoted(value));
      o.body = std::string(value);
      have_body = true;
    } else if (name == "--help" || name == "-h") {
      o.help = true;
    } else if (name == "--exit-when-settled") {
      o.exit_when_settled = true;
    } else if (clients::parse_bus_option(*arg, o.bus)) {
    } else if (name == "--target-rpy") {
      o.target_rpy_deg = clients::parse_vec3(name, value);
    } else if (name == "--max-thrust") {
      o.max_thrust = clients::parse_positive(name, value, "a force in N > 0");
    } else if (name == "--rate") {
      o.rate_hz = clients::parse_positive(name, value, "a rate in Hz > 0");
      if (o.rate_hz > 10000) throw UsageError("--rate: at most 10000 Hz, got " + quoted(value));
    } else if (name == "--arm") {
      o.arm = clients::parse_positive(name, value, "a lever arm in m > 0");
    } else if (name == "--duration") {
      o.duration = clients::parse_positive(name, value, "a duration in seconds > 0");
    } else if (name == "--settle") {
      o.settle_deg = clients::parse_positive(name, value, "an angle in degrees > 0");
    } else if (name == "--timeout") {
      o.timeout = clients::parse_seconds(name, value);
    } else {
      throw UsageError("unknown option " + quoted(name) + " (see --help)");
    }
  }
  return o;
}

std::string usage() {
  std::string text =
      R"(Usage: rigid-attitude [BODY] [--target-rpy R,P,Y] [--max-thrust N] [--rate HZ]
                     [--arm M] [--duration S] [--settle DEG] [--exit-when-settled] [BUS OPTIONS]

An example controller: holds BODY (default: the scene's only body) at a target attitude with six
body-fixed thrusters, reading rigidd's state and publishing their forces (body frame, at body
points) as wrenches at --rate Hz. The thrusters sit in three couples on the faces of the body's
box (or --arm M from its centre for another shape), each bounded to --max-thrust; a cascaded
attitude law (angle -> turn rate -> torque) is allocated to them with no net force. It prints its
attitude error as it goes. Try it on config/scenes/attitude.pbtxt (a box 90 degrees off).

  --target-rpy R,P,Y    target roll, pitch, yaw in degrees (default 0,0,0)
  --max-thrust N        each thruster's bound in N (default 5)
  --rate HZ             control rate (default 100)
  --arm M               thruster lever arm for a body that is not a box
  --duration S          stop after S seconds (default: at SIGINT or SIGTERM)
  --settle DEG          settled: within DEG of the target for 1 s (default 1)
  --exit-when-settled   stop once settled (exit status 1 if --duration ends first)
  --timeout S           how long to wait for rigidd's scene and states (default 5)
)";
  text += clients::bus_options_help();
  text += R"(  -h, --help            show this help

Exit status: 0 done, 1 did not settle in time (--exit-when-settled) or a bus error, 2 a bad
command line, 3 no scene or state from rigidd within the timeout.
)";
  return text;
}

}  // namespace rigid::controllers
