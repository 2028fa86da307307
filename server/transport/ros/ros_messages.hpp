// The small ROS 2 messages rigidd exchanges, in ROS 2's CDR layout (ros/cdr.hpp): rosgraph_msgs/
// Clock out, geometry_msgs/WrenchStamped in, and rmw_dds_common/ParticipantEntitiesInfo (the
// "ros_discovery_info" record through which ROS 2 tools learn which node owns which readers and
// writers). Field order and types follow the .msg files of ROS 2 (rcl_interfaces,
// common_interfaces, rmw_dds_common); a struct's CDR layout is its fields in order, nested structs
// inline.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "rigid/messages.hpp"
#include "transport/decode_status.hpp"

namespace rigid::transport::ros {

// The ROS 2 release a peer runs, where it changes what rigidd sends: Humble's GIDs in
// ros_discovery_info are 24 bytes, Iron's and later ones' 16 (rmw_dds_common/msg/Gid.msg).
enum class Distro : std::uint8_t { kHumble, kJazzy };

// builtin_interfaces/Time (and Duration): int32 sec, uint32 nanosec.
struct RosTime {
  std::int32_t sec = 0;
  std::uint32_t nanosec = 0;
  bool operator==(const RosTime&) const = default;
};

// Simulated seconds as a ROS time: rounded to the nanosecond (a tick of 1/rate_hz s is exact in
// ns for the usual rates), clamped to [0, 2^31) s.
RosTime ros_time(double seconds);

// rosgraph_msgs/msg/Clock.
void encode_clock(RosTime clock, std::vector<std::uint8_t>& out);

// geometry_msgs/msg/WrenchStamped: std_msgs/Header header (stamp, frame_id), geometry_msgs/Wrench
// wrench (Vector3 force, Vector3 torque).
struct WrenchStamped {
  RosTime stamp;
  std::string frame_id;
  Vec3 force{};
  Vec3 torque{};
};
// Longest frame_id accepted: a body's name (kMaxNameLength) with room for a tf prefix.
inline constexpr std::size_t kMaxFrameIdLength = 256;
DecodeStatus decode_wrench_stamped(std::span<const std::uint8_t> bytes, WrenchStamped& out);

// A DDS entity's GUID (16 bytes: participant prefix and entity id), which ROS 2 uses as its GID.
using Guid = std::array<std::uint8_t, 16>;

// One node's entry of rmw_dds_common/msg/ParticipantEntitiesInfo.
struct NodeEntities {
  std::string node_namespace;  // "/" or "/a/b"
  std::string node_name;
  std::vector<Guid> readers;
  std::vector<Guid> writers;
};
void encode_participant_entities(const Guid& participant, const NodeEntities& node, Distro distro,
                                 std::vector<std::uint8_t>& out);

}  // namespace rigid::transport::ros
