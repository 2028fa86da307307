// rigidd's command line: what it accepts and its checks (every error is one line naming the option
// and its value; rigidd then exits with status 2 before anything runs).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>

#include "rigid/messages.hpp"
#include "rigid/names.hpp"
#include "transport/ros/ros_messages.hpp"

namespace rigid::rigidd {

struct RigiddOptions {
  std::optional<std::string> scene;  // --scene; unset: the default scene (default_scene_path)
  bool dds = true;                   // --transport
  bool lcm = true;
  bool transports_given = false;  // --transport was on the command line
  rigid::Mode mode = rigid::Mode::kRealtime;
  std::uint32_t dds_domain = 0;
  std::string lcm_url;  // empty: transport::lcm::kDefaultUrl
  std::string prefix;
  bool reliable_state = false;
  // --rt-workers: realtime mode, the step's other threads at SCHED_FIFO too (loop/server.hpp).
  bool rt_workers = false;
  std::int64_t spin_us = 100;  // realtime: busy-wait this long before each tick's deadline
  // --threads: the threads that step the world, overriding the scene's world { threads } (0:
  // every CPU). Unset: the scene's, else default_threads().
  std::optional<int> threads;
  std::string journal;   // --journal FILE; empty: none
  std::string security;  // --security DIR: DDS Security identity directory; empty: none
  bool controls = true;  // --controls on|off
  // --ros: ROS 2's topics and services on the DDS participant (transport/ros/ros_face.hpp).
  bool ros = false;
  std::string ros_namespace;  // --ros-namespace, normalized: "" or "/a/b"
  transport::ros::Distro ros_distro = transport::ros::Distro::kJazzy;  // --ros-distro
  bool verbose = false;  // --verbose: the lateness histogram at exit
  bool check = false;
  bool help = false;
};

class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Parses the arguments after the program name. Options take their value as the next argument or
// after '=' (--mode=fast). Throws UsageError.
RigiddOptions parse_options(std::span<const std::string_view> args);

// The scene rigidd runs without --scene: config/scenes/default.pbtxt under the current directory
// if it exists (running from a checkout), else the installed one (BINDIR/../share/rigid/scenes),
// else under `source_dir` (the tree rigidd was built from,
// so it also works from the build directory). Throws UsageError naming both places if neither has
// it.
std::string default_scene_path(const std::string& source_dir);

// The physics threads rigidd uses when neither --threads nor the scene says: the CPUs this process
// may run on (its affinity mask) minus one, at least 1. The loop thread is one of them and is
// pinned, with the publishers, to one CPU; the pool's other threads go to the other CPUs (loop/
// server.cpp). One CPU's worth stays free of step work for what is not pinned: each bus's receive
// threads, the journal, housekeeping and the host, so that a step that fills its tick cannot
// delay commands, replies or the bus protocols' own traffic. On two CPUs that is 1 (the loop
// alone). `cpus`: the count to use; <= 0 reads the affinity mask.
int default_threads(int cpus = 0);

std::string usage();

}  // namespace rigid::rigidd
