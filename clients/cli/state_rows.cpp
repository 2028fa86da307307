#include "cli/state_rows.hpp"

#include <array>

#include "util/state_csv.hpp"

namespace rigid::clients {

BodyNames::BodyNames(const rigid::SceneDescription& scene) {
  for (std::size_t i = 0; i < scene.ids.size() && i < scene.names.size(); ++i)
    names_[scene.ids[i]] = scene.names[i];
}

std::string BodyNames::name(std::int32_t id) const {
  const auto it = names_.find(id);
  return it == names_.end() ? std::to_string(id) : it->second;
}

void append_frame_rows(const rigid::StateFrame& f, const BodyNames& names, std::string& out,
                       const std::vector<bool>& only) {
  for (std::size_t i = 0; i < f.body_count(); ++i) {
    if (!only.empty() && (i >= only.size() || !only[i])) continue;
    const double* p = &f.position[3 * i];
    const double* q = &f.orientation[4 * i];
    const double* v = &f.linear_velocity[3 * i];
    const double* w = &f.angular_velocity[3 * i];
    util::append_state_row(
        out, f.sim_time, names.name(f.ids[i]),
        {p[0], p[1], p[2], q[0], q[1], q[2], q[3], v[0], v[1], v[2], w[0], w[1], w[2]});
  }
}

}  // namespace rigid::clients
