// The bodies of a scene by name or id (and, from rigid/names.hpp, the enumerations' names).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "rigid/messages.hpp"
#include "rigid/names.hpp"

namespace rigid::client {

// The enumerations' names (rigid/names.hpp), also under rigid::client.
using rigid::control_name;
using rigid::outcome_name;
using rigid::shape_name;

// The id of body `name_or_id` in `scene` (a name, or a number that is an id); nothing if unknown.
std::optional<std::int32_t> find_body(const SceneDescription& scene, std::string_view name_or_id);
// "a, b, c": the scene's body names, for errors ("none" for an empty scene).
std::string body_list(const SceneDescription& scene);

}  // namespace rigid::client
