#include "transport/ros/sim_services.hpp"

#include "transport/ros/cdr.hpp"

namespace rigid::transport::ros {
namespace {

void header(CdrWriter& w, const RequestHeader& h) {
  w.u64(h.client);
  w.i64(h.seq);
}

void result(CdrWriter& w, SimResult r, std::string_view message) {
  w.u8(static_cast<std::uint8_t>(r));
  w.string(message);
}

// A Vector3's worth of doubles, read and dropped.
void skip_doubles(CdrReader& r, int n) {
  for (int i = 0; i < n; ++i)
    (void)r.f64();
}

// simulation_interfaces/msg/EntityState, read to check it and dropped (rigid cannot set states).
void skip_entity_state(CdrReader& r) {
  (void)r.i32();
  (void)r.u32();
  r.skip_string(kMaxFrameIdLength);
  skip_doubles(r, 7 + 6 + 6);  // pose, twist, acceleration
}

// The longest list a GetEntities filter may carry: a forged count never sizes anything, but a
// request is bounded like every other input.
constexpr std::uint32_t kMaxFilterItems = 1024;

}  // namespace

DecodeStatus decode_request(SimService kind, std::span<const std::uint8_t> bytes, SimRequest& out) {
  CdrReader r(bytes);
  out.header.client = r.u64();
  out.header.seq = r.i64();
  out.other_filters = false;
  switch (kind) {
    case SimService::kGetSimulatorFeatures:
    case SimService::kGetSimulationState:
      // An empty request: ROS 2 adds one uint8 (structure_needs_at_least_one_member), which
      // carries nothing. Not required.
      break;
    case SimService::kSetSimulationState:
      out.state = r.u8();
      break;
    case SimService::kStepSimulation:
      out.steps = r.u64();
      break;
    case SimService::kResetSimulation:
      out.scope = r.u8();
      break;
    case SimService::kGetEntityState:
      r.string(out.entity, kMaxEntityLength);
      break;
    case SimService::kSetEntityState:
      r.string(out.entity, kMaxEntityLength);
      skip_entity_state(r);
      (void)r.boolean();  // set_pose
      (void)r.boolean();  // set_twist
      (void)r.boolean();  // set_acceleration
      break;
    case SimService::kGetEntities: {
      r.string(out.filter, kMaxEntityLength);
      const std::uint32_t categories = r.count(kMaxFilterItems, 1);
      r.skip(categories);
      const std::uint32_t tags = r.count(kMaxFilterItems, 5);
      for (std::uint32_t i = 0; i < tags; ++i)
        r.skip_string(kMaxEntityLength);
      (void)r.u8();  // tags.filter_mode
      const std::uint8_t bounds_type = r.u8();
      const std::uint32_t points = r.count(kMaxFilterItems, 24);
      skip_doubles(r, static_cast<int>(3 * points));
      out.other_filters = categories > 0 || tags > 0 || bounds_type != 0;
      break;
    }
  }
  return r.status();
}

void encode_features_response(const RequestHeader& h, std::span<const std::uint16_t> features,
                              std::string_view custom_info, std::vector<std::uint8_t>& out) {
  CdrWriter w(out);
  header(w, h);
  w.count(features.size());
  for (const std::uint16_t f : features)
    w.u16(f);
  w.count(0);  // spawn_formats
  w.string(custom_info);
}

void encode_result_response(const RequestHeader& h, SimResult r, std::string_view message,
                            std::vector<std::uint8_t>& out) {
  CdrWriter w(out);
  header(w, h);
  result(w, r, message);
}

void encode_simulation_state_response(const RequestHeader& h, SimState state, SimResult r,
                                      std::string_view message, std::vector<std::uint8_t>& out) {
  CdrWriter w(out);
  header(w, h);
  w.u8(static_cast<std::uint8_t>(state));
  result(w, r, message);
}

void encode_entity_state_response(const RequestHeader& h, SimResult r, std::string_view message,
                                  const EntityState& s, std::vector<std::uint8_t>& out) {
  CdrWriter w(out);
  header(w, h);
  result(w, r, message);
  w.i32(s.stamp.sec);
  w.u32(s.stamp.nanosec);
  w.string(s.frame_id);
  for (const double v : s.position)
    w.f64(v);
  w.f64(s.orientation_wxyz[1]);
  w.f64(s.orientation_wxyz[2]);
  w.f64(s.orientation_wxyz[3]);
  w.f64(s.orientation_wxyz[0]);
  for (const double v : s.linear_velocity)
    w.f64(v);
  for (const double v : s.angular_velocity)
    w.f64(v);
  for (int i = 0; i < 6; ++i)
    w.f64(0.0);  // acceleration: linear, angular
}

void encode_entities_response(const RequestHeader& h, SimResult r, std::string_view message,
                              std::span<const std::string_view> entities,
                              std::vector<std::uint8_t>& out) {
  CdrWriter w(out);
  header(w, h);
  result(w, r, message);
  w.count(entities.size());
  for (const std::string_view e : entities)
    w.string(e);
}

}  // namespace rigid::transport::ros
