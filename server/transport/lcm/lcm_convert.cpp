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

void set_counts(std::size_t n, rigid_lcm::SceneInfo& out) {
  out.num_bodies = count(n);
  out.num_inertia = count(6 * n);
  out.num_shape_dims = count(3 * n);
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

bool rows(const rigid_lcm::SceneInfo& in, std::size_t& n) {
  n = static_cast<std::size_t>(in.num_bodies);
  return static_cast<std::size_t>(in.num_inertia) == 6 * n &&
         static_cast<std::size_t>(in.num_shape_dims) == 3 * n;
}

}  // namespace rigid::transport::lcm
