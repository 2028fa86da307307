#include "rigid/client/names.hpp"

#include <charconv>

namespace rigid::client {

std::string_view shape_name(ShapeKind kind) {
  switch (kind) {
    case ShapeKind::kSphere:
      return "sphere";
    case ShapeKind::kBox:
      return "box";
    case ShapeKind::kCylinder:
      return "cylinder";
    case ShapeKind::kEllipsoid:
      return "ellipsoid";
    case ShapeKind::kCapsule:
      return "capsule";
    case ShapeKind::kNone:
      break;
  }
  return "";
}

std::string_view control_name(ControlKind kind) {
  switch (kind) {
    case ControlKind::kPause:
      return "pause";
    case ControlKind::kResume:
      return "resume";
    case ControlKind::kStep:
      return "step";
    case ControlKind::kReset:
      return "reset";
    case ControlKind::kSetRtf:
      return "rate";
    case ControlKind::kNone:
      break;
  }
  return "none";
}

std::string_view outcome_name(Outcome outcome) {
  switch (outcome) {
    case Outcome::kOk:
      return "ok";
    case Outcome::kInvalid:
      return "invalid";
    case Outcome::kNotAllowed:
      return "not allowed";
    case Outcome::kFailed:
      return "failed";
  }
  return "unknown outcome";
}

std::optional<std::int32_t> find_body(const SceneDescription& scene, std::string_view name_or_id) {
  for (std::size_t i = 0; i < scene.names.size(); ++i)
    if (scene.names[i] == name_or_id) return scene.ids[i];
  std::int32_t id = 0;
  const auto [end, ec] =
      std::from_chars(name_or_id.data(), name_or_id.data() + name_or_id.size(), id);
  if (ec == std::errc() && end == name_or_id.data() + name_or_id.size()) {
    for (const std::int32_t known : scene.ids)
      if (known == id) return id;
  }
  return std::nullopt;
}

std::string body_list(const SceneDescription& scene) {
  std::string text;
  for (const std::string& n : scene.names)
    text += (text.empty() ? "" : ", ") + n;
  return text.empty() ? "none" : text;
}

}  // namespace rigid::client
