#include "transport/ros/ros_names.hpp"

namespace rigid::transport::ros {
namespace {

bool token_char(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
}

// The first invalid position of a relative name, or npos.
std::size_t first_invalid(std::string_view name) {
  if (name.empty()) return 0;
  bool token_start = true;
  for (std::size_t i = 0; i < name.size(); ++i) {
    const char c = name[i];
    if (c == '/') {
      if (token_start) return i;  // "//" or a leading '/'
      token_start = true;
      continue;
    }
    if (!token_char(c) || (token_start && c >= '0' && c <= '9')) return i;
    token_start = false;
  }
  return token_start ? name.size() - 1 : std::string_view::npos;  // a trailing '/'
}

}  // namespace

std::optional<std::string> normalize_namespace(std::string_view ns, std::string* why) {
  while (!ns.empty() && ns.front() == '/')
    ns.remove_prefix(1);
  while (!ns.empty() && ns.back() == '/')
    ns.remove_suffix(1);
  if (ns.empty()) return std::string();
  if (ns.size() > kMaxNamespaceLength) {
    if (why != nullptr) *why = "longer than " + std::to_string(kMaxNamespaceLength) + " characters";
    return std::nullopt;
  }
  const std::size_t bad = first_invalid(ns);
  if (bad != std::string_view::npos) {
    if (why != nullptr) {
      const char c = ns[bad];
      *why = c == '/'                 ? "an empty token ('//')"
             : (c >= '0' && c <= '9') ? std::string("a token starting with the digit '") + c + "'"
                                      : std::string("the character '") + c +
                                            "' (ROS names allow letters, digits, '_' and '/')";
    }
    return std::nullopt;
  }
  return "/" + std::string(ns);
}

bool is_valid_relative_name(std::string_view name) {
  return first_invalid(name) == std::string_view::npos;
}

std::string dds_topic(std::string_view fq_name) {
  return "rt" + std::string(fq_name);
}

std::string dds_request_topic(std::string_view fq_service) {
  return "rq" + std::string(fq_service) + "Request";
}

std::string dds_reply_topic(std::string_view fq_service) {
  return "rr" + std::string(fq_service) + "Reply";
}

std::string dds_message_type(std::string_view package, std::string_view name) {
  return std::string(package) + "::msg::dds_::" + std::string(name) + "_";
}

std::string dds_request_type(std::string_view package, std::string_view service) {
  return std::string(package) + "::srv::dds_::" + std::string(service) + "_Request_";
}

std::string dds_response_type(std::string_view package, std::string_view service) {
  return std::string(package) + "::srv::dds_::" + std::string(service) + "_Response_";
}

}  // namespace rigid::transport::ros
