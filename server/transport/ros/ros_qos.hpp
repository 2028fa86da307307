// The QoS ROS 2 endpoints use, as rmw_cyclonedds maps a ROS QoS profile onto DDS, and the
// "key=value;" USER_DATA it carries (participant "enclave", service endpoints' "serviceid" and
// "clientid").
#pragma once

#include <dds/dds.h>

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "transport/dds/dds_entity.hpp"
#include "transport/ros/ros_messages.hpp"

namespace rigid::transport::ros {

enum class Durability : std::uint8_t { kVolatile, kTransientLocal };

// A reliable keep-last `depth` QoS. Writers do not dispose on deletion (rmw's choice, so a reader
// sees its writer go as "no writers"); transient local keeps `depth` samples for late readers.
// A reliable writer waits at most 10 ms for a slow reader's acknowledgements (rmw waits forever:
// rigidd's publishers never block for long). user_data: added when not empty.
dds::Qos ros_qos(Durability durability, std::int32_t depth, std::string_view user_data = {});

// The value of `key` in an endpoint's or participant's USER_DATA, nullopt when absent.
std::optional<std::string> user_data_value(const dds_qos_t* qos, std::string_view key);

// An entity's GUID (its ROS 2 GID).
Guid guid_of(dds_entity_t entity);

}  // namespace rigid::transport::ros
