#include "common/contact_csv.hpp"

#include "rigid/names.hpp"
#include "util/state_csv.hpp"

namespace rigid::common {

ContactNames::ContactNames(const rigid::SceneDescription& scene) : parts_(scene.part_names) {
  for (std::size_t i = 0; i < scene.ids.size() && i < scene.names.size(); ++i) {
    const std::int32_t id = scene.ids[i];
    if (id < 0 || static_cast<std::size_t>(id) >= rigid::kMaxBodies) continue;
    if (static_cast<std::size_t>(id) >= bodies_.size())
      bodies_.resize(static_cast<std::size_t>(id) + 1);
    bodies_[static_cast<std::size_t>(id)] = scene.names[i];
  }
}

std::string ContactNames::body(std::int32_t id) const {
  if (id >= 0 && static_cast<std::size_t>(id) < bodies_.size() &&
      !bodies_[static_cast<std::size_t>(id)].empty()) {
    return bodies_[static_cast<std::size_t>(id)];
  }
  return std::to_string(id);
}

std::string ContactNames::part(std::int32_t index) const {
  if (index < 0) return {};  // a separate event: the body left all its supports
  if (index >= 0 && static_cast<std::size_t>(index) < parts_.size() &&
      !parts_[static_cast<std::size_t>(index)].empty()) {
    return parts_[static_cast<std::size_t>(index)];
  }
  return std::to_string(index);
}

void append_contact_rows(const rigid::ContactEvents& events, const ContactNames& names,
                         std::string& out) {
  for (std::size_t i = 0; i < events.event_count(); ++i) {
    out += std::to_string(events.tick);
    out += ',';
    util::append_number(out, events.times[i]);
    out += ',';
    out += rigid::contact_name(events.kinds[i]);
    out += ',';
    // Names are restricted by the scene loader to characters that need no CSV quoting.
    out += names.body(events.bodies[i]);
    out += ',';
    out += names.part(events.parts[i]);
    for (const std::vector<double>* v : {&events.position, &events.normal, &events.impulse}) {
      for (std::size_t k = 0; k < 3; ++k) {
        out += ',';
        util::append_number(out, (*v)[3 * i + k]);
      }
    }
    out += '\n';
  }
}

}  // namespace rigid::common
