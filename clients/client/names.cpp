#include "rigid/client/names.hpp"

#include <charconv>

namespace rigid::client {

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
