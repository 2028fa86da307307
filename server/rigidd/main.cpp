// rigidd: the daemon. Wiring only: the command line (rigidd_options), the scene (scene/), the
// loop and its threads (loop/server.hpp), the buses (transport/), signals (signal_watcher) and
// systemd (systemd_notifier). The main thread ends up waiting for a signal, pinging systemd.
#include <malloc.h>
#include <signal.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "common/state_conversion.hpp"
#include "loop/log.hpp"
#include "loop/server.hpp"
#include "rigidd/memory_lock.hpp"
#include "rigidd/rigidd_options.hpp"
#include "rigidd/systemd_notifier.hpp"
#include "scene/scene.hpp"
#include "transport/dds/dds_transport.hpp"
#include "transport/lcm/lcm_transport.hpp"
#include "transport/ros/ros_face.hpp"
#include "util/signal_watcher.hpp"

namespace {

using namespace rigid;
using namespace std::chrono_literals;

std::string number(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", v);
  return buffer;
}

std::string describe(const scene::Scene& s, const rigidd::RigiddOptions& o) {
  std::string text =
      s.path + " (" + std::to_string(s.world.bodies.size()) + " bodies, " + number(s.rate_hz) +
      " Hz, " + std::to_string(s.substeps) + " substep(s), state every " +
      std::to_string(s.publish_every) + " tick(s): " + number(s.rate_hz / s.publish_every) +
      " Hz, " +
      (s.world.threads == 0 ? std::string("a physics thread per CPU")
                            : std::to_string(s.world.threads) + " physics thread(s)") +
      (o.threads         ? " (--threads)"
       : s.threads_given ? " (scene)"
                         : "") +
      ")";
  text += ", mode " + std::string(rigid::mode_name(o.mode));
  if (o.rt_workers) text += ", step workers at real-time priority (--rt-workers)";
  return text;
}

std::string buses(const rigidd::RigiddOptions& o, const std::string& lcm_url) {
  std::string text;
  if (o.dds) {
    text += "dds domain " + std::to_string(o.dds_domain);
    if (o.reliable_state) text += " (reliable state)";
    text += o.security.empty() ? " (no security: trusts every process that reaches it)"
                               : " (DDS Security, identity " + o.security + ")";
  }
  if (o.lcm) {
    text += std::string(text.empty() ? "" : ", ") + "lcm " + lcm_url +
            " (no security: trusts every process that reaches it)";
  }
  if (o.ros) {
    text += ", ROS 2 node " + (o.ros_namespace.empty() ? std::string() : o.ros_namespace) +
            "/rigidd (" +
            (o.ros_distro == transport::ros::Distro::kHumble ? "humble" : "iron and later") + ")";
  }
  if (!o.controls) text += ", controls off";
  if (!o.prefix.empty()) text += ", prefix " + o.prefix;
  return text;
}

// What rigidd --ros needs of the scene and the command line (transport/ros/ros_face.hpp).
transport::ros::Options ros_options(const scene::Scene& scene, const rigidd::RigiddOptions& o) {
  transport::ros::Options ros;
  ros.ns = o.ros_namespace;
  ros.distro = o.ros_distro;
  ros.mode = o.mode;
  ros.secure = !o.security.empty();
  ros.wrench_ttl = scene.limits.max_ttl;
  ros.body_names.reserve(scene.world.bodies.size());
  for (const physics::BodySpec& b : scene.world.bodies)
    ros.body_names.push_back(b.name);
  // The static parts, for /tf_static and the markers: a plane's frame at its point nearest the
  // origin, z along its normal (common::plane_frame, as SceneInfo carries it); a fixed shape's at
  // its pose.
  for (const physics::PlaneSpec& p : scene.world.planes) {
    transport::ros::StaticFrame f;
    f.name = p.name;
    f.plane = true;
    const common::PlaneFrame s = common::plane_frame(p);
    f.p_WS = {s.p_WS.x(), s.p_WS.y(), s.p_WS.z()};
    f.q_WS_wxyz = {s.q_WS.w(), s.q_WS.x(), s.q_WS.y(), s.q_WS.z()};
    ros.static_frames.push_back(std::move(f));
  }
  for (const physics::StaticSpec& s : scene.world.statics) {
    transport::ros::StaticFrame f;
    f.name = s.name;
    f.p_WS = {s.p_WS.x(), s.p_WS.y(), s.p_WS.z()};
    f.q_WS_wxyz = {s.q_WS.w(), s.q_WS.x(), s.q_WS.y(), s.q_WS.z()};
    f.shape = common::shape_kind(s.shape.kind);
    const physics::Vec3 d = common::shape_dims(s.shape);
    f.dims = {d.x(), d.y(), d.z()};
    ros.static_frames.push_back(std::move(f));
  }
  return ros;
}

// The scene file's text for the journal, read again after load_scene (which keeps only the result).
std::string scene_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in) throw std::runtime_error(path + ": cannot read the scene again for the journal");
  return text.str();
}

int run(const rigidd::RigiddOptions& options, scene::Scene scene) {
  // Block SIGTERM and SIGINT before any thread exists (the buses start threads), so that only
  // the signalfd sees them.
  util::SignalWatcher signals({SIGTERM, SIGINT});
  // A 1000-body state is ~110 KB: above glibc's default mmap threshold every serialization buffer
  // would be mapped and unmapped, page-faulting on each publish.
  mallopt(M_MMAP_THRESHOLD, 256 * 1024 * 1024);
  mallopt(M_TRIM_THRESHOLD, 512 * 1024 * 1024);

  loop::FdLog log("rigidd");
  for (const std::string& w : scene.warnings)
    log.line(w);
  loop::ServerOptions server_options;
  server_options.mode = options.mode;
  server_options.controls = options.controls;
  server_options.secure = !options.security.empty();
  server_options.spin_ns = options.spin_us * 1000;
  server_options.realtime_workers = options.rt_workers;
  if (!options.journal.empty()) {
    server_options.journal_path = options.journal;
    server_options.scene_text = scene_text(scene.path);
  }
  loop::Server server(scene, server_options, log);
  // --ros: what ROS's face needs of the scene (transport/ros/ros_face.hpp).
  transport::ros::Options ros;
  transport::ros::Plan ros_plan;
  if (options.ros) {
    ros = ros_options(scene, options);
    ros_plan = transport::ros::plan(ros);
    for (const std::string& note : ros_plan.notes)
      log.line("--ros: " + note);
  }
  // The server keeps what it needs of the scene (the world its compact copy of the bodies): the
  // rest, ~400 B a body, goes now rather than stay resident for the daemon's life.
  const std::size_t bodies = scene.world.bodies.size();
  const std::string description = describe(scene, options);
  scene = scene::Scene{};
  // DDS stays on loopback unless a network is configured (CYCLONEDDS_URI).
  const std::string dds_config = options.dds ? transport::dds::ensure_dds_config() : "";
  if (options.dds) {
    // Its own largest samples (a state: ~110 B a body; a scene: ~300 B a body) with room to
    // spare, and at least 1 MiB: anything larger from outside is dropped before reassembly.
    transport::dds::limit_sample_size(std::max<std::size_t>(
        1 << 20, 2 * std::max(400 * bodies + 65536, ros_plan.largest_sample)));
  }
  const std::string lcm_url =
      options.lcm_url.empty() ? std::string(transport::lcm::kDefaultUrl) : options.lcm_url;
  try {
    if (options.dds) {
      transport::dds::Options o;
      o.role = transport::Role::kServer;
      o.domain = options.dds_domain;
      o.prefix = options.prefix;
      o.reliable_state = options.reliable_state;
      o.security = options.security;
      server.add_transport(
          transport::dds::make_transport(o, server.receiver(rigid::Bus::kDds),
                                         options.ros ? transport::ros::make_face(ros) : nullptr));
    }
    if (options.lcm) {
      transport::lcm::Options o;
      o.role = transport::Role::kServer;
      o.url = lcm_url;
      o.prefix = options.prefix;
      server.add_transport(transport::lcm::make_transport(o, server.receiver(rigid::Bus::kLcm)));
    }
  } catch (const transport::TransportError& e) {
    log.line(e.what());
    return 1;
  }

  rigidd::SystemdNotifier systemd;
  server.start();
  // What loading and starting freed (the scene's text and parsed message, the world's build
  // scratch, the DDS SceneInfo's) goes back to the system: below the trim threshold set above,
  // glibc would keep it resident.
  malloc_trim(0);
  // Only what a real-time loop needs; after the trim, since a locked page cannot be given back.
  if (options.mode == rigid::Mode::kRealtime) log.line(rigidd::lock_memory());
  log.line("started: " + description + "; " + buses(options, lcm_url) +
           (options.journal.empty() ? "" : "; journal " + options.journal) +
           (options.dds ? "; " + dds_config : ""));

  bool ready = false;
  std::uint64_t last_beat = server.heartbeat();
  auto next_ping = std::chrono::steady_clock::now();
  for (;;) {
    const std::optional<int> signal = signals.wait(50ms);
    if (signal) {
      log.line(std::string(signal == SIGTERM ? "SIGTERM" : "SIGINT") + ": stopping");
      break;
    }
    if (!ready && server.first_state_sent()) {
      ready = true;
      systemd.ready();
      systemd.status("running " + description);
      log.line("ready: first state published");
    }
    if (const auto period = systemd.watchdog_period()) {
      const auto now = std::chrono::steady_clock::now();
      if (now >= next_ping) {
        // Only a loop that has moved since the last ping earns one.
        const std::uint64_t beat = server.heartbeat();
        if (beat != last_beat) systemd.watchdog();
        last_beat = beat;
        next_ping = now + *period;
      }
    }
  }
  systemd.stopping();
  server.stop();
  if (options.verbose) {
    log.line(server.closing_line());
    log.line(server.lateness_histogram_line());
  } else {
    log.line(server.short_closing_line());
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string_view> args(argv + 1, argv + argc);
  rigidd::RigiddOptions options;
  scene::Scene scene;
  try {
    options = rigidd::parse_options(args);
    if (options.help) {
      std::cout << rigidd::usage();
      return 0;
    }
    const std::string path =
        options.scene ? *options.scene : rigidd::default_scene_path(RIGID_SOURCE_DIR);
    scene = scene::load_scene(path);
    // --threads, else the scene's world { threads }, else what the machine can give the loop.
    if (options.threads) {
      scene.world.threads = *options.threads;
    } else if (!scene.threads_given) {
      scene.world.threads = rigidd::default_threads();
    }
  } catch (const rigidd::UsageError& e) {
    std::cerr << "rigidd: " << e.what() << '\n';
    return 2;
  } catch (const scene::SceneError& e) {
    std::cerr << e.what() << '\n';
    return 2;
  }
  if (options.check) {
    for (const std::string& w : scene.warnings)
      std::cerr << w << '\n';
    if (options.ros) {
      for (const std::string& note : transport::ros::plan(ros_options(scene, options)).notes)
        std::cerr << "rigidd: --ros: " << note << '\n';
    }
    std::cout << "rigidd: ok: " << describe(scene, options) << '\n';
    return 0;
  }
  try {
    return run(options, std::move(scene));
  } catch (const std::exception& e) {
    std::cerr << "rigidd: " << e.what() << '\n';
    return 1;
  }
}
