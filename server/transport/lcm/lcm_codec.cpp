#include "transport/lcm/lcm_codec.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cassert>
#include <cstring>
#include <exception>
#include <limits>
#include <string>
#include <tuple>
#include <type_traits>
#include <vector>

#include "transport/codec_impl.hpp"
#include "transport/lcm/lcm_convert.hpp"
#include "transport/lcm/lcm_layout_check.hpp"

namespace rigid::transport::lcm {

// One message type's scratch: separate messages for the encoding and the decoding side, so the two
// may run on different threads.
template <class LcmType>
struct LcmSlot {
  LcmType outgoing{};
  std::vector<std::uint8_t> bytes;
  LcmType incoming{};
};

namespace {

using K = FieldLayout::Kind;

// The encoded layouts of msgs/rigid.lcm, field by field. A mismatch with the .lcm file makes valid
// messages fail this check, which the round-trip tests catch.
constexpr FieldLayout kCount{K::kCount};
constexpr FieldLayout kI8{K::kInt8};
constexpr FieldLayout kI32{K::kInt32};
constexpr FieldLayout kI64{K::kInt64};
constexpr FieldLayout kF64{K::kDouble};
constexpr FieldLayout kStr{K::kString};
constexpr FieldLayout kVec3{K::kDouble, 3};
constexpr FieldLayout fixed(K kind, std::int32_t n) {
  return {kind, n};
}
constexpr FieldLayout counted(K kind, std::int32_t count_field) {
  return {kind, 1, count_field};
}

constexpr std::array kWorldStateLayout{
    kCount,                  // num_bodies
    kCount,                  // num_xyz
    kCount,                  // num_wxyz
    kI64,                    // tick
    kF64,                    // sim_time
    kI64,                    // stamp_ns
    counted(K::kInt32, 0),   // ids
    counted(K::kDouble, 1),  // position
    counted(K::kDouble, 2),  // orientation
    counted(K::kDouble, 1),  // linear_velocity
    counted(K::kDouble, 1),  // angular_velocity
};

constexpr std::array kWrenchLayout{
    kI64,   // source
    kI64,   // seq
    kI32,   // key
    kI32,   // body_id
    kStr,   // body_name
    kVec3,  // force
    kVec3,  // point
    kI32,   // force_frame
    kVec3,  // torque
    kI32,   // torque_frame
    kF64,   // ttl
    kI64,   // stamp_ns
};

constexpr std::array kControlLayout{
    kI64,  // source
    kI64,  // seq
    kI32,  // command
    kI64,  // steps
    kF64,  // rtf
};

constexpr std::array kEditLayout{
    kI64,                  // source
    kI64,                  // seq
    kI32,                  // kind
    kI32,                  // body_id
    kStr,                  // body_name
    kI32,                  // set
    kVec3,                 // position
    fixed(K::kDouble, 4),  // orientation
    kVec3,                 // linear_velocity
    kI32,                  // velocity_frame
    kVec3,                 // angular_velocity
    kI32,                  // angular_velocity_frame
    kI64,                  // stamp_ns
};

constexpr std::array kControlReplyLayout{
    kI64,  // source
    kI64,  // seq
    kI32,  // command
    kI32,  // outcome
    kI64,  // tick
    kStr,  // message
};

constexpr std::array kStatsLayout{
    kCount,                  // num_refused_sources
    kI64,                    // tick
    kF64,                    // sim_time
    kI32,                    // mode
    kI8,                     // paused
    fixed(K::kDouble, 5),    // rtf_last_second .. lateness_max_us
    kI64,                    // overruns
    fixed(K::kDouble, 2),    // step_cost_p50_us, step_cost_max_us
    kI64,                    // bodies_frozen
    kI64,                    // large_rotation_steps
    kI64,                    // states_skipped
    kI64,                    // commands_accepted
    fixed(K::kInt64, 10),    // rejected (RejectCounts, inline)
    fixed(K::kInt64, 4),     // dds (TransportCounts, inline)
    fixed(K::kInt64, 4),     // lcm
    counted(K::kString, 0),  // refused_sender
    counted(K::kInt64, 0),   // refused_count
    counted(K::kString, 0),  // refused_last_reason
};

constexpr std::array kSceneInfoLayout{
    kCount,                  // num_bodies
    kCount,                  // num_inertia
    kCount,                  // num_shape_dims
    kCount,                  // num_parts
    kCount,                  // num_part_xyz
    kCount,                  // num_part_wxyz
    kStr,                    // scene_name
    kF64,                    // dt
    kI32,                    // substeps
    kI32,                    // publish_every
    kVec3,                   // gravity
    kStr,                    // integrator
    kF64,                    // max_force
    kF64,                    // max_torque
    kF64,                    // max_ttl
    kI32,                    // max_wrenches_per_source
    kF64,                    // max_commands_per_second
    counted(K::kInt32, 0),   // ids
    counted(K::kString, 0),  // names
    counted(K::kDouble, 0),  // masses
    counted(K::kDouble, 1),  // inertia
    counted(K::kInt32, 0),   // shape_kinds
    counted(K::kDouble, 2),  // shape_dims
    counted(K::kString, 3),  // part_names
    counted(K::kInt32, 3),   // part_kinds
    counted(K::kDouble, 4),  // part_position
    counted(K::kDouble, 5),  // part_orientation
    counted(K::kDouble, 4),  // part_dims
    counted(K::kDouble, 3),  // part_restitution
    counted(K::kDouble, 3),  // part_friction
};

constexpr std::array kContactEventsLayout{
    kCount,                  // num_events
    kCount,                  // num_xyz
    kI64,                    // tick
    kF64,                    // sim_time
    kI64,                    // stamp_ns
    kI64,                    // dropped
    counted(K::kInt32, 0),   // kinds
    counted(K::kInt32, 0),   // bodies
    counted(K::kInt32, 0),   // parts
    counted(K::kDouble, 0),  // times
    counted(K::kDouble, 1),  // position
    counted(K::kDouble, 1),  // normal
    counted(K::kDouble, 1),  // impulse
};

constexpr std::array kAcceptedCommandLayout{
    kI64,                  // tick
    kI32,                  // kind
    kI64,                  // source
    kI64,                  // seq
    kI32,                  // key
    kI32,                  // body_id
    kVec3,                 // force
    kVec3,                 // point
    kI32,                  // force_frame
    kVec3,                 // torque
    kI32,                  // torque_frame
    kF64,                  // ttl
    kI32,                  // command
    kI64,                  // steps
    kF64,                  // rtf
    kI32,                  // edit
    kI32,                  // set
    kVec3,                 // position
    fixed(K::kDouble, 4),  // orientation
    kVec3,                 // linear_velocity
    kI32,                  // velocity_frame
    kVec3,                 // angular_velocity
    kI32,                  // angular_velocity_frame
    kI64,                  // stamp_ns
};

// The layout of the message carrying Plain.
template <class Plain>
constexpr const auto& layout_for() {
  if constexpr (std::is_same_v<Plain, StateFrame>) return kWorldStateLayout;
  if constexpr (std::is_same_v<Plain, WrenchCommand>) return kWrenchLayout;
  if constexpr (std::is_same_v<Plain, ControlCommand>) return kControlLayout;
  if constexpr (std::is_same_v<Plain, ControlReply>) return kControlReplyLayout;
  if constexpr (std::is_same_v<Plain, StatsReport>) return kStatsLayout;
  if constexpr (std::is_same_v<Plain, SceneDescription>) return kSceneInfoLayout;
  if constexpr (std::is_same_v<Plain, AcceptedCommand>) return kAcceptedCommandLayout;
  if constexpr (std::is_same_v<Plain, ContactEvents>) return kContactEventsLayout;
  if constexpr (std::is_same_v<Plain, EditCommand>) return kEditLayout;
}

template <class LcmType, class Plain>
std::span<const std::uint8_t> encode_with(LcmSlot<LcmType>& slot, const Plain& message) {
  if (!to_lcm(message, slot.outgoing)) return {};
  const int size = slot.outgoing.getEncodedSize();
  slot.bytes.resize(static_cast<std::size_t>(size));
  if (slot.outgoing.encode(slot.bytes.data(), 0, size) != size) return {};
  return slot.bytes;
}

template <class LcmType, class Plain, std::size_t N>
DecodeStatus decode_with(LcmSlot<LcmType>& slot, const std::array<FieldLayout, N>& layout,
                         std::span<const std::uint8_t> payload, Plain& out) {
  if (payload.size() > static_cast<std::size_t>(std::numeric_limits<int>::max())) {
    return DecodeStatus::kMalformed;
  }
  const DecodeStatus checked = check_layout(payload, LcmType::getHash(), layout);
  if (checked != DecodeStatus::kOk) return checked;
  const int size = static_cast<int>(payload.size());
  try {
    if (slot.incoming.decode(payload.data(), 0, size) != size) return DecodeStatus::kMalformed;
  } catch (const std::exception&) {
    // Only memory exhaustion can get here once the layout has been checked.
    return DecodeStatus::kMalformed;
  }
  return from_lcm(slot.incoming, out);
}

// Big-endian writes into a buffer sized beforehand, as lcm-gen's encoders write.
class BigEndian {
 public:
  explicit BigEndian(std::uint8_t* at) : at_(at) {}
  void put(std::uint32_t v) {
    v = __builtin_bswap32(v);
    std::memcpy(at_, &v, sizeof v);
    at_ += sizeof v;
  }
  void put(std::uint64_t v) {
    v = __builtin_bswap64(v);
    std::memcpy(at_, &v, sizeof v);
    at_ += sizeof v;
  }
  void put(std::int32_t v) { put(static_cast<std::uint32_t>(v)); }
  void put(std::int64_t v) { put(static_cast<std::uint64_t>(v)); }
  void put(double v) { put(std::bit_cast<std::uint64_t>(v)); }
  // An LCM string: its length with the terminating NUL, its bytes, the NUL.
  void put(const std::string& s) {
    put(static_cast<std::int32_t>(s.size() + 1));
    std::memcpy(at_, s.data(), s.size());
    at_ += s.size();
    *at_++ = 0;
  }
  // A whole array in one loop the compiler turns into vector byte shuffles.
  template <class T>
  void put_all(const std::vector<T>& values) {
    for (const T v : values)
      put(v);
  }
  std::uint8_t* at() const { return at_; }

 private:
  std::uint8_t* at_;
};

}  // namespace
}  // namespace rigid::transport::lcm

namespace rigid::transport {

template <>
struct CodecBuffers<Bus::kLcm> {
  template <class Plain>
  using SlotOf = lcm::LcmSlot<typename lcm::LcmTypeOf<Plain>::type>;

  // The state and the scene are written by hand (below); every other message through lcm-gen's
  // type.
  std::span<const std::uint8_t> encode(const StateFrame& m);
  std::span<const std::uint8_t> encode(const SceneDescription& m);
  template <class Plain>
  std::span<const std::uint8_t> encode(const Plain& message) {
    return lcm::encode_with(std::get<SlotOf<Plain>>(slots), message);
  }
  template <class Plain>
  DecodeStatus decode(std::span<const std::uint8_t> payload, Plain& out) {
    return lcm::decode_with(std::get<SlotOf<Plain>>(slots), lcm::layout_for<Plain>(), payload, out);
  }

  std::tuple<SlotOf<StateFrame>, SlotOf<WrenchCommand>, SlotOf<ControlCommand>,
             SlotOf<ControlReply>, SlotOf<StatsReport>, SlotOf<SceneDescription>,
             SlotOf<AcceptedCommand>, SlotOf<ContactEvents>, SlotOf<EditCommand>>
      slots;
};

// A state is written straight from the frame into its payload: through rigid_lcm::WorldState (as
// the commands, replies and stats still are) it was copied once more on the way, which cost the
// publisher a second state's memory (10 MB at 10^5 bodies) and a pass over it per state. The bytes
// are those rigid_lcm::WorldState::encode writes (transport_codec_test holds the two to the same
// bytes).
std::span<const std::uint8_t> CodecBuffers<Bus::kLcm>::encode(const StateFrame& m) {
  const std::size_t n = m.body_count();
  if (!m.lengths_agree() || n > kMaxBodies) return {};
  std::vector<std::uint8_t>& bytes = std::get<SlotOf<StateFrame>>(slots).bytes;
  // Fingerprint, three counts, tick, sim_time, stamp_ns, the ids, 13 doubles a body.
  bytes.resize(8 + 3 * 4 + 3 * 8 + n * (4 + 13 * 8));
  lcm::BigEndian out(bytes.data());
  out.put(rigid_lcm::WorldState::getHash());
  out.put(static_cast<std::int32_t>(n));
  out.put(static_cast<std::int32_t>(3 * n));
  out.put(static_cast<std::int32_t>(4 * n));
  out.put(m.tick);
  out.put(m.sim_time);
  out.put(m.stamp_ns);
  out.put_all(m.ids);
  out.put_all(m.position);
  out.put_all(m.orientation);
  out.put_all(m.linear_velocity);
  out.put_all(m.angular_velocity);
  assert(out.at() == bytes.data() + bytes.size());
  return bytes;
}
// The scene, too, is written straight into its payload (the bytes rigid_lcm::SceneInfo::encode
// writes; transport_codec_test holds the two to the same bytes). rigidd republishes it every second
// on LCM, so through lcm-gen's type it kept a second copy of the scene (~120 B a body: ids, names,
// masses, inertia, shapes) for its whole life and copied the scene into it once a second.
std::span<const std::uint8_t> CodecBuffers<Bus::kLcm>::encode(const SceneDescription& m) {
  const std::size_t n = m.body_count();
  const std::size_t parts = m.part_count();
  if (!m.lengths_agree() || n > kMaxBodies || parts > kMaxParts) return {};
  // lcm-gen encodes a string up to its first NUL but sizes it by size(): it refused a string
  // holding a NUL (its encode fell short of its size), and so does this.
  const auto lcm_string = [](const std::string& s) { return s.find('\0') == std::string::npos; };
  if (!lcm_string(m.scene_name) || !lcm_string(m.integrator) ||
      !std::all_of(m.names.begin(), m.names.end(), lcm_string) ||
      !std::all_of(m.part_names.begin(), m.part_names.end(), lcm_string)) {
    return {};
  }
  const auto string_size = [](const std::string& s) { return 4 + s.size() + 1; };
  std::size_t size = 8 + 6 * 4 + string_size(m.scene_name) + 8 + 2 * 4 + 3 * 8 +
                     string_size(m.integrator) + 3 * 8 + 4 + 8 + n * (4 + 8 + 6 * 8 + 4 + 3 * 8) +
                     parts * (4 + 3 * 8 + 4 * 8 + 3 * 8 + 2 * 8);
  for (const std::string& name : m.names)
    size += string_size(name);
  for (const std::string& name : m.part_names)
    size += string_size(name);
  // lcm_publish takes the size as an unsigned int, lcm-gen as an int.
  if (size > static_cast<std::size_t>(std::numeric_limits<int>::max())) return {};
  std::vector<std::uint8_t>& bytes = std::get<SlotOf<SceneDescription>>(slots).bytes;
  bytes.resize(size);
  lcm::BigEndian out(bytes.data());
  out.put(rigid_lcm::SceneInfo::getHash());
  out.put(static_cast<std::int32_t>(n));
  out.put(static_cast<std::int32_t>(6 * n));
  out.put(static_cast<std::int32_t>(3 * n));
  out.put(static_cast<std::int32_t>(parts));
  out.put(static_cast<std::int32_t>(3 * parts));
  out.put(static_cast<std::int32_t>(4 * parts));
  out.put(m.scene_name);
  out.put(m.dt);
  out.put(m.substeps);
  out.put(m.publish_every);
  for (const double g : m.gravity)
    out.put(g);
  out.put(m.integrator);
  out.put(m.max_force);
  out.put(m.max_torque);
  out.put(m.max_ttl);
  out.put(m.max_wrenches_per_source);
  out.put(m.max_commands_per_second);
  out.put_all(m.ids);
  for (const std::string& name : m.names)
    out.put(name);
  out.put_all(m.masses);
  out.put_all(m.inertia);
  for (const ShapeKind kind : m.shape_kinds)
    out.put(static_cast<std::int32_t>(kind));
  out.put_all(m.shape_dims);
  for (const std::string& name : m.part_names)
    out.put(name);
  for (const ShapeKind kind : m.part_kinds)
    out.put(static_cast<std::int32_t>(kind));
  out.put_all(m.part_position);
  out.put_all(m.part_orientation);
  out.put_all(m.part_dims);
  out.put_all(m.part_restitution);
  out.put_all(m.part_friction);
  assert(out.at() == bytes.data() + bytes.size());
  return bytes;
}

template class Codec<Bus::kLcm>;

}  // namespace rigid::transport
