// The CSV format of body states: one row per body and time, world-frame quantities, every number
// with 17 significant digits so that a double survives the round trip through text.
#pragma once

#include <array>
#include <string>
#include <string_view>

#include "physics/world.hpp"

namespace rigid::sim {

inline constexpr std::string_view kStateCsvHeader = "t,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz\n";

// Appends one row per body of the world's current state to `out`.
void append_state_rows(const physics::World& world, std::string& out);

// Appends one row: t, the body's name, then x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz (for tools that
// write states they received, such as rigid-record export, in the same format).
void append_state_row(std::string& out, double t, std::string_view body,
                      const std::array<double, 13>& values);

}  // namespace rigid::sim
