// Scene files: protobuf text format (msgs/rigid.proto) -> a validated physics::WorldSpec.
//
// Every problem a user can put in a scene file is reported as a SceneError whose what() is one
// line, "FILE:LINE:COL: message", pointing at the field at fault and naming its value. Nothing is
// returned unless the whole scene is valid, including everything the physics::World constructor
// checks.
#pragma once

#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "physics/inertia.hpp"
#include "physics/spec.hpp"

namespace rigid::scene {

// The longest body name: names travel on the buses as bounded strings (msgs/rigid.idl,
// string<128>; rigid::kMaxNameLength).
inline constexpr std::size_t kMaxBodyNameLength = 128;

// Bounds the daemon enforces on commands from the network.
struct Limits {
  double max_force = 1e6;                 // N
  double max_torque = 1e6;                // N m
  double max_ttl = 60.0;                  // s
  int max_wrenches_per_source = 64;       // live wrenches one sender may hold
  double max_commands_per_second = 2000;  // per sender
};

struct Scene {
  // world.dt = 1 / (rate_hz * substeps).
  physics::WorldSpec world;
  double rate_hz = 1000.0;  // ticks per second
  int substeps = 1;         // physics steps per tick
  int publish_every = 1;    // ticks between published states
  // world { threads } was given (world.threads then holds it): a program that has its own default
  // (rigidd) uses that only when the scene is silent.
  bool threads_given = false;
  Limits limits;
  // The material of bodies and parts that give none (world.material).
  physics::Surface world_surface;
  // One line each, "FILE:LINE:COL: warning: ...", for things the loader fixed or that look
  // unintended.
  std::vector<std::string> warnings;
  // The file name (or the name given to parse_scene).
  std::string path;
  // Each body's shape as the file gave it (none when its inertia was given directly), for the
  // daemon's SceneInfo; parallel to world.bodies.
  std::vector<std::optional<physics::Shape>> shapes;
};

class SceneError : public std::runtime_error {
 public:
  // line and column are 1-based; line 0 means the problem has no position (e.g. unreadable file),
  // and then what() is "FILE: message".
  SceneError(std::string file, int line, int column, std::string message);

  const std::string& file() const { return file_; }
  int line() const { return line_; }
  int column() const { return column_; }
  // The message without the "FILE:LINE:COL: " prefix.
  const std::string& message() const { return message_; }

 private:
  std::string file_;
  int line_;
  int column_;
  std::string message_;
};

// Reads, parses and validates a scene file. Throws SceneError.
Scene load_scene(const std::string& path);
// Parses and validates scene text; `name` stands for the file in messages. Throws SceneError.
Scene parse_scene(std::string_view text, std::string_view name);

}  // namespace rigid::scene
