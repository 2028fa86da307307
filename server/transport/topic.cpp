#include "transport/topic.hpp"

#include <algorithm>

namespace rigid::transport {
namespace {

constexpr std::array<std::string_view, kAllTopics.size()> kDdsNames{
    "rigid/state", "rigid/wrench",   "rigid/control",  "rigid/control_reply", "rigid/stats",
    "rigid/scene", "rigid/accepted", "rigid/contacts", "rigid/edit"};
constexpr std::array<std::string_view, kAllTopics.size()> kLcmNames{
    "RIGID_STATE", "RIGID_WRENCH",   "RIGID_CONTROL",  "RIGID_CONTROL_REPLY", "RIGID_STATS",
    "RIGID_SCENE", "RIGID_ACCEPTED", "RIGID_CONTACTS", "RIGID_EDIT"};

TopicNames join(std::string_view prefix, char separator,
                const std::array<std::string_view, kAllTopics.size()>& names) {
  TopicNames out;
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (!prefix.empty()) {
      out[i].append(prefix);
      out[i].push_back(separator);
    }
    out[i].append(names[i]);
  }
  return out;
}

}  // namespace

std::string_view to_string(Topic topic) {
  static constexpr std::array<std::string_view, kAllTopics.size()> kNames{
      "state", "wrench",   "control",  "control_reply", "stats",
      "scene", "accepted", "contacts", "edit"};
  return kNames.at(index_of(topic));
}

bool is_valid_prefix(std::string_view prefix) {
  return std::all_of(prefix.begin(), prefix.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
  });
}

TopicNames dds_topic_names(std::string_view prefix) {
  return join(prefix, '/', kDdsNames);
}

TopicNames lcm_channel_names(std::string_view prefix) {
  return join(prefix, '_', kLcmNames);
}

}  // namespace rigid::transport
