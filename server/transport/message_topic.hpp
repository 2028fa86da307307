// Which topic carries each plain message type, and which role publishes it.
#pragma once

#include "rigid/messages.hpp"
#include "transport/topic.hpp"
#include "transport/transport.hpp"

namespace rigid::transport {

template <class Message>
struct TopicOf;  // defined for the eight messages only
template <>
struct TopicOf<StateFrame> {
  static constexpr Topic value = Topic::kState;
};
template <>
struct TopicOf<WrenchCommand> {
  static constexpr Topic value = Topic::kWrench;
};
template <>
struct TopicOf<ControlCommand> {
  static constexpr Topic value = Topic::kControl;
};
template <>
struct TopicOf<ControlReply> {
  static constexpr Topic value = Topic::kControlReply;
};
template <>
struct TopicOf<StatsReport> {
  static constexpr Topic value = Topic::kStats;
};
template <>
struct TopicOf<SceneDescription> {
  static constexpr Topic value = Topic::kScene;
};
template <>
struct TopicOf<AcceptedCommand> {
  static constexpr Topic value = Topic::kAccepted;
};
template <>
struct TopicOf<ContactEvents> {
  static constexpr Topic value = Topic::kContacts;
};
template <>
struct TopicOf<EditCommand> {
  static constexpr Topic value = Topic::kEdit;
};

// The server publishes everything but the commands; clients publish only the commands.
constexpr bool publishes(Role role, Topic topic) {
  return (role == Role::kClient) == is_command(topic);
}

}  // namespace rigid::transport
