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

bool rows(const rigid_SceneInfo& in, std::size_t& n) {
  n = in.ids._length;
  return in.names._length == n && in.masses._length == n && in.inertia._length == 6 * n &&
         in.shape_kinds._length == n && in.shape_dims._length == 3 * n;
}

}  // namespace rigid::transport::dds
