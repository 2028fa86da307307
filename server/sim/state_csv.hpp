// rigid-sim's CSV of the world's body states (the format: util/state_csv.hpp).
#pragma once

#include <string>

#include "physics/world.hpp"
#include "util/state_csv.hpp"

namespace rigid::sim {

// Appends one row per body of the world's current state to `out`.
void append_state_rows(const physics::World& world, std::string& out);
}  // namespace rigid::sim
