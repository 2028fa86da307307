#include "transport/dds/dds_convert.hpp"

namespace rigid::transport::dds {

bool rows(const rigid_WorldState& in, std::size_t& n) {
  n = in.ids._length;
  return in.position._length == 3 * n && in.orientation._length == 4 * n &&
         in.linear_velocity._length == 3 * n && in.angular_velocity._length == 3 * n;
}

bool rows(const rigid_Stats& in, std::size_t& n) {
  n = in.refused_sender._length;
  return in.refused_count._length == n && in.refused_last_reason._length == n;
}

bool rows(const rigid_SceneInfo& in, wire::SceneRows& rows) {
  const std::size_t n = in.ids._length;
  const std::size_t m = in.part_names._length;
  rows = {n, m};
  return in.names._length == n && in.masses._length == n && in.inertia._length == 6 * n &&
         in.shape_kinds._length == n && in.shape_dims._length == 3 * n &&
         in.part_kinds._length == m && in.part_position._length == 3 * m &&
         in.part_orientation._length == 4 * m && in.part_dims._length == 3 * m &&
         in.part_restitution._length == m && in.part_friction._length == m;
}

bool rows(const rigid_ContactEvents& in, std::size_t& n) {
  n = in.kinds._length;
  return in.bodies._length == n && in.parts._length == n && in.times._length == n &&
         in.position._length == 3 * n && in.normal._length == 3 * n && in.impulse._length == 3 * n;
}

}  // namespace rigid::transport::dds
