// The world's body states as rows of the state CSV (the format: util/state_csv.hpp), for rigid-sim
// and the replay.
#pragma once

#include <string>

#include "physics/world.hpp"
#include "util/state_csv.hpp"

namespace rigid::common {

// Appends one row per body of the world's current state to `out`.
void append_state_rows(const physics::World& world, std::string& out);
}  // namespace rigid::common
