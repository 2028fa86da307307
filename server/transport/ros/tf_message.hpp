// tf2_msgs/msg/TFMessage (geometry_msgs/TransformStamped[] transforms) for a fixed list of child
// frames under one parent, serialized once and then patched: each state rewrites only the stamps
// and the seven doubles of each transform, in place, so that publishing /tf costs a copy of the
// poses rather than a serialization of every name on every state.
//
// TransformStamped: std_msgs/Header header (builtin_interfaces/Time stamp, string frame_id),
// string child_frame_id, geometry_msgs/Transform transform (Vector3 translation, Quaternion
// rotation as x, y, z, w).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "rigid/messages.hpp"
#include "transport/ros/ros_messages.hpp"

namespace rigid::transport::ros {

class TfMessage {
 public:
  // One transform per child, in order, parent -> children[i]; poses identity, stamp zero.
  void build(std::string_view parent, std::span<const std::string> children);
  std::size_t size() const { return pose_at_.size(); }

  void set_stamp(RosTime stamp);
  // Transform i: translation p (x, y, z) and rotation q as w, x, y, z (rigid's order; ROS's is
  // x, y, z, w), copied bit for bit.
  void set_pose(std::size_t i, const double* p, const double* q_wxyz);
  // Every transform from a state whose bodies are, in order, the children this was built with:
  // stamp = the state's simulated time, poses = its positions and orientations.
  void fill(const StateFrame& state);

  std::span<const std::uint8_t> bytes() const { return bytes_; }

 private:
  std::vector<std::uint8_t> bytes_;
  std::vector<std::size_t> stamp_at_;  // byte offsets of each header stamp
  std::vector<std::size_t> pose_at_;   // byte offsets of each translation (rotation follows)
};

}  // namespace rigid::transport::ros
