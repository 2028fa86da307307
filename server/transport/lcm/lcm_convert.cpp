#include "transport/lcm/lcm_convert.hpp"

namespace rigid::transport::lcm {
namespace {

std::int32_t count(std::size_t n) {
  return static_cast<std::int32_t>(n);
}

}  // namespace

void set_counts(std::size_t n, rigid_lcm::WorldState& out) {
  out.num_bodies = count(n);
  out.num_xyz = count(3 * n);
  out.num_wxyz = count(4 * n);
}

void set_counts(std::size_t n, rigid_lcm::Stats& out) {
  out.num_refused_sources = count(n);
}

void set_counts(const wire::SceneRows& n, rigid_lcm::SceneInfo& out) {
  out.num_bodies = count(n.bodies);
  out.num_inertia = count(6 * n.bodies);
  out.num_shape_dims = count(3 * n.bodies);
  out.num_parts = count(n.parts);
  out.num_part_xyz = count(3 * n.parts);
  out.num_part_wxyz = count(4 * n.parts);
}

void set_counts(std::size_t n, rigid_lcm::ContactEvents& out) {
  out.num_events = count(n);
  out.num_xyz = count(3 * n);
}

bool rows(const rigid_lcm::WorldState& in, std::size_t& n) {
  n = static_cast<std::size_t>(in.num_bodies);
  return static_cast<std::size_t>(in.num_xyz) == 3 * n &&
         static_cast<std::size_t>(in.num_wxyz) == 4 * n;
}

bool rows(const rigid_lcm::Stats& in, std::size_t& n) {
  n = static_cast<std::size_t>(in.num_refused_sources);
  return n <= kMaxRefusedSources;
}

bool rows(const rigid_lcm::SceneInfo& in, wire::SceneRows& rows) {
  const auto n = static_cast<std::size_t>(in.num_bodies);
  const auto m = static_cast<std::size_t>(in.num_parts);
  rows = {n, m};
  return static_cast<std::size_t>(in.num_inertia) == 6 * n &&
         static_cast<std::size_t>(in.num_shape_dims) == 3 * n &&
         static_cast<std::size_t>(in.num_part_xyz) == 3 * m &&
         static_cast<std::size_t>(in.num_part_wxyz) == 4 * m;
}

bool rows(const rigid_lcm::ContactEvents& in, std::size_t& n) {
  n = static_cast<std::size_t>(in.num_events);
  return n <= kMaxContactEvents && static_cast<std::size_t>(in.num_xyz) == 3 * n;
}

}  // namespace rigid::transport::lcm
