#include "transport/ros/ros_messages.hpp"

#include <cmath>

#include "transport/ros/cdr.hpp"

namespace rigid::transport::ros {

RosTime ros_time(double seconds) {
  if (!(seconds > 0.0)) return {};  // also NaN
  constexpr double kMax = 2147483647.999999999;
  const double s = std::min(seconds, kMax);
  const auto ns = static_cast<std::int64_t>(std::llround(s * 1e9));
  return {static_cast<std::int32_t>(std::min<std::int64_t>(ns / 1'000'000'000, 2147483647)),
          static_cast<std::uint32_t>(ns % 1'000'000'000)};
}

void encode_clock(RosTime clock, std::vector<std::uint8_t>& out) {
  CdrWriter w(out);
  w.i32(clock.sec);
  w.u32(clock.nanosec);
}

DecodeStatus decode_wrench_stamped(std::span<const std::uint8_t> bytes, WrenchStamped& out) {
  CdrReader r(bytes);
  out.stamp.sec = r.i32();
  out.stamp.nanosec = r.u32();
  r.string(out.frame_id, kMaxFrameIdLength);
  for (double& v : out.force)
    v = r.f64();
  for (double& v : out.torque)
    v = r.f64();
  return r.status();
}

void encode_participant_entities(const Guid& participant, const NodeEntities& node, Distro distro,
                                 std::vector<std::uint8_t>& out) {
  // Gid: char[24] data (Humble) or char[16] data (Iron and later), the GUID then zeros.
  const std::size_t gid_size = distro == Distro::kHumble ? 24 : 16;
  CdrWriter w(out);
  const auto gid = [&](const Guid& g) {
    w.bytes(g);
    for (std::size_t i = g.size(); i < gid_size; ++i)
      w.u8(0);
  };
  gid(participant);
  w.count(1);  // node_entities_info_seq
  w.string(node.node_namespace);
  w.string(node.node_name);
  w.count(node.readers.size());
  for (const Guid& g : node.readers)
    gid(g);
  w.count(node.writers.size());
  for (const Guid& g : node.writers)
    gid(g);
}

}  // namespace rigid::transport::ros
