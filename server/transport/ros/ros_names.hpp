// ROS 2 names and how rmw_cyclonedds puts them on DDS: a topic "/a/b" is the DDS topic "rt/a/b",
// a service "/a/s" the topics "rq/a/sRequest" and "rr/a/sReply"; a message type pkg/msg/Name is
// the DDS type "pkg::msg::dds_::Name_", a service's request and response
// "pkg::srv::dds_::Name_Request_" and "pkg::srv::dds_::Name_Response_".
//
// Names follow rmw's validation (rmw/validate_full_topic_name.c): tokens of ASCII letters, digits
// and '_', separated by single '/', none starting with a digit.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace rigid::transport::ros {

// rmw's limit on a fully qualified topic name (RMW_TOPIC_MAX_NAME_LENGTH: 255 less room for the
// "rq/" prefix and "Request" suffix of a service).
inline constexpr std::size_t kMaxTopicNameLength = 247;
// rigidd's limit on --ros-namespace, so that "/NS/rigid/BODY/wrench" fits in the above for any
// body name (at most 128 characters).
inline constexpr std::size_t kMaxNamespaceLength = 100;

// "a/b", "/a/b" or "/a/b/" -> "/a/b"; "" or "/" -> "" (the root namespace). nullopt for a name
// that is not a valid ROS namespace or longer than kMaxNamespaceLength; `why` then says what is
// wrong, naming the character.
std::optional<std::string> normalize_namespace(std::string_view ns, std::string* why);

// A relative name made of tokens ("rigid/craft/wrench"): true if every token is valid.
bool is_valid_relative_name(std::string_view name);

// The DDS names.
std::string dds_topic(std::string_view fq_name);  // "rt" + name
std::string dds_request_topic(std::string_view fq_service);
std::string dds_reply_topic(std::string_view fq_service);
std::string dds_message_type(std::string_view package, std::string_view name);
std::string dds_request_type(std::string_view package, std::string_view service);
std::string dds_response_type(std::string_view package, std::string_view service);

}  // namespace rigid::transport::ros
