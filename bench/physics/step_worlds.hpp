// The worlds of step_bench (Google Benchmark, timed) and step_run (a fixed number of steps, for
// instruction counts under callgrind), so that both measure the same bodies: N bodies of one case,
// initial conditions spread a little so that no two bodies are identical.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "physics/world.hpp"

namespace rigid::bench {

enum class StepCase {
  kRacket,         // tennis-racket flip: I = (1, 2, 3), w0 = (1e-3, 5, 1e-3)
  kSphere,         // I = 0.4 (1, 1, 1), moving and spinning
  kTop,            // axisymmetric, I = (1, 1, 1.8), w0 = (1, 0, 20)
  kPoint,          // point masses under gravity
  kThruster,       // off-centre body-fixed thruster on a general body
  kTorquedTop,     // the top under a constant world torque (loaded axisymmetric bodies)
  kTorquedSphere,  // the sphere under a constant body torque (loaded isotropic bodies)
  kLeverTop        // forced_bench's symmetric top: a prolate top under a world force at its axis
};

std::optional<StepCase> find_step_case(std::string_view name);
physics::WorldSpec make_step_world(StepCase c, int n, const std::string& integrator);

}  // namespace rigid::bench
