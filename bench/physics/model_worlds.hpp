// The benchmark worlds of one body model each, shared by throughput.cpp (cost per body-step
// against N) and memory_bench.cpp (bytes per body at 10^6), so that both measure the same bodies;
// and the process's memory readings both take around a World's construction.
#pragma once

#include <optional>
#include <span>
#include <string_view>

#include "physics/world.hpp"

namespace rigid::bench {

// One body of each of the four motion groups a World compiles bodies into (body_motion.hpp's
// BodyMotion: point mass, sphere, axisymmetric and general body), torque-free but for the point
// mass, which falls under gravity; and the general body again under an off-centre body-fixed
// force, where every integrator must evaluate the load at each of its stages.
enum class Model { kPoint, kIsotropic, kAxisymmetric, kGeneral, kGeneralForced };

struct ModelInfo {
  Model model;
  const char* name;
  const char* body;  // for reports
};

std::span<const ModelInfo> all_models();
std::optional<Model> find_model(std::string_view name);

// n bodies of `model`, dt = 1 ms, differing a little in their initial angular velocity so that no
// two are the same.
physics::WorldSpec make_model_world(Model model, int n);

// Bytes of heap in use (glibc's mallinfo2) and resident (/proc/self/statm).
double heap_bytes();
double rss_bytes();

}  // namespace rigid::bench
