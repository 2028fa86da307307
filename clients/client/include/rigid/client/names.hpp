// Names for what travels: control requests and their outcomes as rigidctl prints them, and the
// bodies of a scene by name or id.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "rigid/messages.hpp"

namespace rigid::client {

// "pause", "resume", "step", "reset", "rate".
std::string_view control_name(ControlKind kind);
// "ok", "invalid", "not allowed", "failed".
std::string_view outcome_name(Outcome outcome);
// "sphere", "box", "cylinder", "ellipsoid", "capsule"; "" for none (or an unknown value).
std::string_view shape_name(ShapeKind kind);

// The id of body `name_or_id` in `scene` (a name, or a number that is an id); nothing if unknown.
std::optional<std::int32_t> find_body(const SceneDescription& scene, std::string_view name_or_id);
// "a, b, c": the scene's body names, for errors ("none" for an empty scene).
std::string body_list(const SceneDescription& scene);

}  // namespace rigid::client
