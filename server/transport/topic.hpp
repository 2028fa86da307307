// The streams rigid exchanges and their names on each bus. A prefix lets two servers share one
// network: with prefix "lab", DDS topics are "lab/rigid/state", ... and LCM channels
// "lab_RIGID_STATE", ... An empty prefix gives the plain names.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace rigid::transport {

enum class Topic : std::uint8_t {
  kState,
  kWrench,
  kControl,
  kControlReply,
  kStats,
  kScene,
  kAccepted,
  kContacts,
  kEdit,
};

inline constexpr std::array<Topic, 9> kAllTopics{
    Topic::kState, Topic::kWrench,   Topic::kControl,  Topic::kControlReply, Topic::kStats,
    Topic::kScene, Topic::kAccepted, Topic::kContacts, Topic::kEdit,
};

// The topics clients send on and the server reads.
constexpr bool is_command(Topic topic) {
  return topic == Topic::kWrench || topic == Topic::kControl || topic == Topic::kEdit;
}

inline constexpr std::size_t index_of(Topic topic) {
  return static_cast<std::size_t>(topic);
}

std::string_view to_string(Topic topic);

// A prefix is empty or made of ASCII letters, digits and '_': safe as part of a DDS topic name and
// inside the regular expression LCM subscribes with.
bool is_valid_prefix(std::string_view prefix);

// Names of every topic on one bus, indexed by index_of(Topic).
using TopicNames = std::array<std::string, kAllTopics.size()>;

// The caller checks the prefix with is_valid_prefix first.
TopicNames dds_topic_names(std::string_view prefix);
TopicNames lcm_channel_names(std::string_view prefix);

}  // namespace rigid::transport
