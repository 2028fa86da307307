#include "transport/ros/tf_message.hpp"

#include <cstring>

#include "transport/ros/cdr.hpp"

namespace rigid::transport::ros {

void TfMessage::build(std::string_view parent, std::span<const std::string> children) {
  stamp_at_.clear();
  pose_at_.clear();
  stamp_at_.reserve(children.size());
  pose_at_.reserve(children.size());
  CdrWriter w(bytes_);
  w.count(children.size());
  for (const std::string& child : children) {
    stamp_at_.push_back(w.position_for(4));
    w.i32(0);
    w.u32(0);
    w.string(parent);
    w.string(child);
    pose_at_.push_back(w.position_for(8));
    for (int k = 0; k < 3; ++k)
      w.f64(0.0);
    for (int k = 0; k < 3; ++k)
      w.f64(0.0);
    w.f64(1.0);  // w: identity
  }
}

void TfMessage::set_stamp(RosTime stamp) {
  std::uint8_t raw[8];
  std::memcpy(raw, &stamp.sec, 4);
  std::memcpy(raw + 4, &stamp.nanosec, 4);
  for (const std::size_t at : stamp_at_)
    std::memcpy(bytes_.data() + at, raw, sizeof raw);
}

void TfMessage::set_pose(std::size_t i, const double* p, const double* q_wxyz) {
  const double pose[7] = {p[0], p[1], p[2], q_wxyz[1], q_wxyz[2], q_wxyz[3], q_wxyz[0]};
  std::memcpy(bytes_.data() + pose_at_[i], pose, sizeof pose);
}

void TfMessage::fill(const StateFrame& state) {
  // One pass in the message's order (each transform's stamp, then its pose).
  const RosTime t = ros_time(state.sim_time);
  std::uint8_t stamp[8];
  std::memcpy(stamp, &t.sec, 4);
  std::memcpy(stamp + 4, &t.nanosec, 4);
  const std::size_t n = std::min(size(), state.body_count());
  for (std::size_t i = 0; i < n; ++i) {
    std::memcpy(bytes_.data() + stamp_at_[i], stamp, sizeof stamp);
    set_pose(i, &state.position[3 * i], &state.orientation[4 * i]);
  }
}

}  // namespace rigid::transport::ros
