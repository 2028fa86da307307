#include "rigidd/rigidd_options.hpp"

#include <sched.h>

#include <algorithm>
#include <charconv>
#include <filesystem>
#include <system_error>

#include "transport/ros/ros_names.hpp"
#include "transport/topic.hpp"

namespace rigid::rigidd {
namespace {

constexpr std::string_view kDefaultScene = "config/scenes/default.pbtxt";
// The scene's own bound on world { threads } (scene.cpp).
constexpr int kMaxThreads = 256;
// DDS maps domain ids to UDP ports; with the default port mapping ids above 232 do not fit.
constexpr std::uint32_t kMaxDomain = 232;

std::string quoted(std::string_view s) {
  return "'" + std::string(s) + "'";
}

void parse_transports(std::string_view list, RigiddOptions& o) {
  o.dds = o.lcm = false;
  std::string_view rest = list;
  for (;;) {
    const std::size_t comma = rest.find(',');
    const std::string_view name = rest.substr(0, comma);
    if (name == "dds") {
      o.dds = true;
    } else if (name == "lcm") {
      o.lcm = true;
    } else {
      throw UsageError("--transport: expected a comma-separated list of dds and lcm, got " +
                       quoted(list));
    }
    if (comma == std::string_view::npos) break;
    rest = rest.substr(comma + 1);
  }
}

}  // namespace

RigiddOptions parse_options(std::span<const std::string_view> args) {
  RigiddOptions o;
  bool ros_options = false;  // --ros-namespace or --ros-distro given
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string_view arg = args[i];
    if (arg == "--help" || arg == "-h") {
      o.help = true;
      continue;
    }
    if (arg == "--check") {
      o.check = true;
      continue;
    }
    if (arg == "--verbose") {
      o.verbose = true;
      continue;
    }
    if (arg == "--reliable-state") {
      o.reliable_state = true;
      continue;
    }
    if (arg == "--rt-workers") {
      o.rt_workers = true;
      continue;
    }
    if (arg == "--ros") {
      o.ros = true;
      continue;
    }
    if (arg.empty() || arg[0] != '-') {
      throw UsageError("unexpected argument " + quoted(arg) + " (the scene is given with --scene)");
    }
    std::string_view name = arg;
    std::optional<std::string_view> value;
    if (const auto eq = arg.find('='); eq != std::string_view::npos) {
      name = arg.substr(0, eq);
      value = arg.substr(eq + 1);
    }
    if (name != "--scene" && name != "--transport" && name != "--mode" && name != "--dds-domain" &&
        name != "--lcm-url" && name != "--prefix" && name != "--spin-us" && name != "--journal" &&
        name != "--security" && name != "--controls" && name != "--threads" &&
        name != "--ros-namespace" && name != "--ros-distro") {
      throw UsageError("unknown option " + quoted(name) + " (see --help)");
    }
    if (!value) {
      if (i + 1 >= args.size()) throw UsageError(std::string(name) + " needs a value");
      value = args[++i];
    }
    if (name == "--scene") {
      if (value->empty()) throw UsageError("--scene: expected a file name, got ''");
      o.scene = std::string(*value);
    } else if (name == "--transport") {
      parse_transports(*value, o);
      o.transports_given = true;
    } else if (name == "--mode") {
      if (*value == "realtime") {
        o.mode = rigid::Mode::kRealtime;
      } else if (*value == "fast") {
        o.mode = rigid::Mode::kFast;
      } else if (*value == "lockstep") {
        o.mode = rigid::Mode::kLockstep;
      } else {
        throw UsageError("--mode: expected realtime, fast or lockstep, got " + quoted(*value));
      }
    } else if (name == "--dds-domain") {
      std::uint32_t d = 0;
      const auto [end, ec] = std::from_chars(value->data(), value->data() + value->size(), d);
      if (ec != std::errc() || end != value->data() + value->size() || d > kMaxDomain) {
        throw UsageError("--dds-domain: expected an integer 0 .. 232, got " + quoted(*value));
      }
      o.dds_domain = d;
    } else if (name == "--spin-us") {
      std::int64_t us = 0;
      const auto [end, ec] = std::from_chars(value->data(), value->data() + value->size(), us);
      if (ec != std::errc() || end != value->data() + value->size() || us < 0 || us > 1'000'000) {
        throw UsageError("--spin-us: expected microseconds 0 .. 1000000, got " + quoted(*value));
      }
      o.spin_us = us;
    } else if (name == "--threads") {
      int n = 0;
      const auto [end, ec] = std::from_chars(value->data(), value->data() + value->size(), n);
      if (ec != std::errc() || end != value->data() + value->size() || n < 0 || n > kMaxThreads) {
        throw UsageError("--threads: expected 0 (every CPU) .. 256, got " + quoted(*value));
      }
      o.threads = n;
    } else if (name == "--journal") {
      if (value->empty()) throw UsageError("--journal: expected a file name, got ''");
      o.journal = std::string(*value);
    } else if (name == "--security") {
      if (value->empty()) throw UsageError("--security: expected an identity directory, got ''");
      o.security = std::string(*value);
    } else if (name == "--controls") {
      if (*value == "on") {
        o.controls = true;
      } else if (*value == "off") {
        o.controls = false;
      } else {
        throw UsageError("--controls: expected on or off, got " + quoted(*value));
      }
    } else if (name == "--ros-namespace") {
      std::string why;
      const std::optional<std::string> ns = transport::ros::normalize_namespace(*value, &why);
      if (!ns)
        throw UsageError("--ros-namespace: " + quoted(*value) + " is not a ROS namespace: " + why);
      o.ros_namespace = *ns;
      ros_options = true;
    } else if (name == "--ros-distro") {
      if (*value == "humble") {
        o.ros_distro = transport::ros::Distro::kHumble;
      } else if (*value == "iron" || *value == "jazzy" || *value == "kilted" ||
                 *value == "rolling") {
        o.ros_distro = transport::ros::Distro::kJazzy;
      } else {
        throw UsageError("--ros-distro: expected humble, iron, jazzy, kilted or rolling, got " +
                         quoted(*value));
      }
      ros_options = true;
    } else if (name == "--lcm-url") {
      if (value->find("://") == std::string_view::npos) {
        throw UsageError(
            "--lcm-url: expected an LCM URL such as udpm://239.255.76.67:7667?ttl=0, "
            "got " +
            quoted(*value));
      }
      o.lcm_url = std::string(*value);
    } else {
      if (!transport::is_valid_prefix(*value)) {
        throw UsageError("--prefix: expected letters, digits and '_' only, got " + quoted(*value));
      }
      o.prefix = std::string(*value);
    }
  }
  // Secure by default: with DDS Security, the unauthenticated LCM bus only if asked for.
  if (!o.security.empty() && !o.transports_given) o.lcm = false;
  if (!o.security.empty() && !o.dds) {
    throw UsageError("--security applies to DDS, which --transport leaves out");
  }
  if (ros_options && !o.ros) throw UsageError("--ros-namespace and --ros-distro apply to --ros");
  if (o.ros && !o.dds) throw UsageError("--ros speaks on DDS, which --transport leaves out");
  if (o.rt_workers && o.mode != rigid::Mode::kRealtime) {
    throw UsageError("--rt-workers applies to --mode realtime, not " + quoted(mode_name(o.mode)));
  }
  return o;
}

int default_threads(int cpus) {
  if (cpus <= 0) {
    cpu_set_t set;
    CPU_ZERO(&set);
    cpus = sched_getaffinity(0, sizeof set, &set) == 0 ? CPU_COUNT(&set) : 1;
  }
  return std::clamp(cpus - 1, 1, kMaxThreads);
}

std::string default_scene_path(const std::string& source_dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_regular_file(fs::path(kDefaultScene), ec)) return std::string(kDefaultScene);
  // An installed rigidd: PREFIX/bin/rigidd finds PREFIX/share/rigid/scenes/default.pbtxt.
  const fs::path program = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const fs::path installed =
        (program.parent_path() / RIGID_DATADIR_FROM_BINDIR / "rigid/scenes/default.pbtxt")
            .lexically_normal();
    if (fs::is_regular_file(installed, ec)) return installed.string();
  }
  const fs::path built_from = fs::path(source_dir) / kDefaultScene;
  if (fs::is_regular_file(built_from, ec)) return built_from.string();
  throw UsageError("no --scene given, and " + std::string(kDefaultScene) +
                   " is neither under the current directory, nor installed beside rigidd, nor "
                   "under " +
                   source_dir + " (give --scene FILE)");
}

std::string usage() {
  return R"(Usage: rigidd [--scene FILE] [--transport dds,lcm] [--mode realtime|fast|lockstep]
              [--dds-domain N] [--lcm-url URL] [--prefix P] [--reliable-state]
              [--spin-us N] [--threads N] [--rt-workers] [--journal FILE]
              [--security DIR] [--controls on|off] [--ros] [--ros-namespace NS]
              [--ros-distro NAME] [--verbose] [--check]

Runs the rigid-body scene FILE at its fixed rate, publishes the state over Cyclone DDS and LCM,
and takes wrenches (forces at body points) and control requests from clients on both buses.

  --scene FILE       the scene (protobuf text format); default config/scenes/default.pbtxt under
                     the current directory, else the installed one (PREFIX/share/rigid/scenes),
                     else under the source tree rigidd was built from
  --transport LIST   the buses: dds, lcm or dds,lcm (default both)
  --mode MODE        realtime: ticks at the scene's rate_hz (default); fast: as fast as possible;
                     lockstep: a tick only on step requests
  --dds-domain N     DDS domain id, 0 .. 232 (default 0); CYCLONEDDS_URI configures the network
  --lcm-url URL      LCM URL (default udpm://239.255.76.67:7667?ttl=0: stays on this host)
  --prefix P         prefix for topic names (P/rigid/state, P_RIGID_STATE), so that two servers
                     can share a network; letters, digits and '_'
  --reliable-state   publish the state reliably on DDS instead of best-effort keep-last 1
  --spin-us N        realtime mode: sleep to N microseconds before each tick's deadline, then
                     busy-wait to it, so that wake-up latency does not make ticks late (default
                     100; 0: sleep only)
  --threads N        threads that step the world, 0 .. 256 (0: every CPU), overriding the
                     scene's world { threads }; default the scene's, else the CPUs rigidd may
                     use minus one (at least 1): the loop thread and its publishers keep one
                     CPU, the other step threads run on the others, and one CPU's worth is left
                     to the buses' receive threads. States are bit-identical for any count
  --rt-workers       realtime mode with --threads 2 or more: the other step threads run at
                     SCHED_FIFO too (one below the publishers, on the CPUs other than the
                     loop's), so that no process of normal priority can preempt one in the
                     middle of its share of a step, which the loop then waits for. For a host
                     whose other CPUs can be given to rigidd's step: it then takes them at
                     real-time priority for the step's length each tick. Off by default:
                     where other processes need those CPUs it can make ticks later instead
  --journal FILE     write every command accepted, with the tick at which it took effect, and
                     a hash of every state published to FILE (created; an existing file is
                     refused): rigid-sim --replay FILE re-runs the session bit for bit
  --security DIR     DDS Security: authenticate with the identity directory DIR (rigid-keys add
                     KEYSTORE rigidd --may serve makes one; rigid-keys init makes it for you);
                     only authenticated identities then see the state or move a body, each
                     command counts as its identity's, and LCM is off unless --transport names
                     it (LCM has no security: it trusts every process that reaches it)
  --controls on|off  accept pause, resume, step, reset and rate requests (default on). With
                     --security only identities that may control can send them anyway
  --ros              also be a ROS 2 node on the DDS participant: /tf, /tf_static, /clock and
                     rigid/markers from every state, geometry_msgs/WrenchStamped on
                     rigid/BODY/wrench, and the simulation_interfaces services under
                     /rigidd (docs/ros2.md); under the Cyclone configuration a ROS 2 user has
                     (config/cyclonedds-ros.xml: multicast discovery on this host)
  --ros-namespace NS the ROS namespace of rigidd's node and topics (default: none)
  --ros-distro NAME  the ROS 2 release of the peers: humble (24-byte GIDs in
                     ros_discovery_info) or iron, jazzy, kilted, rolling (default jazzy)
  --verbose          at exit, the full summary (percentiles, states per bus, command-to-state
                     latency) and the whole run's tick lateness histogram
  --check            validate the command line and the scene, print a summary and exit
  -h, --help         show this help

Signals: SIGTERM or SIGINT stop it cleanly (exit status 0). Under systemd (Type=notify) it sends
READY=1 after the first state is published, WATCHDOG=1 while its loop runs, STOPPING=1 on exit.
Every accepted command is also published on rigid/accepted (LCM: RIGID_ACCEPTED).
Exit status: 0 stopped by a signal (or --check passed), 1 a bus or the journal could not be set
up, 2 a bad command line or scene.
)";
}

}  // namespace rigid::rigidd
