// The CSV format of body states: one row per body and time, world-frame quantities, every number
// with 17 significant digits so that a double survives the round trip through text. rigid-sim
// writes it from the world (common/world_csv.hpp), the tools from received states.
#pragma once

#include <array>
#include <string>
#include <string_view>

namespace rigid::util {

inline constexpr std::string_view kStateCsvHeader = "t,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz\n";

// Appends x with 17 significant digits (as printf's %.17g, whatever the C locale's decimal point):
// it reads back as the same double.
void append_number(std::string& out, double x);

// Appends one row: t, the body's name, then x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz.
void append_state_row(std::string& out, double t, std::string_view body,
                      const std::array<double, 13>& values);

}  // namespace rigid::util
