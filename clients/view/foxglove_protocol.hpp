// The Foxglove WebSocket protocol (subprotocol foxglove.websocket.v1, Foxglove's published
// specification) as rigid-view speaks it, as pure functions (no I/O): what it advertises, its
// JSON texts, the Message Data header, and the client's messages, checked. docs/foxglove.md.
//
// Server -> client: serverInfo (capabilities: clientPublish unless --read-only), advertise (the
// channels below, protobuf, each schema a FileDescriptorSet in base64), status, and Message Data
// (binary: u8 0x01, u32 subscription id, u64 timestamp in ns, the message; little-endian).
// Client -> server: subscribe / unsubscribe, advertise / unadvertise of a client channel (only
// kPushTopic, json), and Client Message Data (binary: u8 0x01, u32 client channel id, payload).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "rigid/messages.hpp"

namespace rigid::view::foxglove {

inline constexpr std::string_view kSubprotocol = "foxglove.websocket.v1";

// The channels rigid-view serves, with their ids (advertised; never reused for another topic).
enum class Channel : std::uint32_t {
  kTransforms = 1,  // /rigid/transforms   foxglove.FrameTransforms, per state
  kBodies = 2,      // /rigid/bodies       foxglove.SceneUpdate, at subscribe and per scene
  kBodyStates = 3,  // /rigid/body_states  rigid.msgs.BodyStates, per state (plots)
  kState = 4,       // /rigid/state        rigid.msgs.StateRecord, per state (as the MCAP export)
  kScene = 5,       // /rigid/scene        rigid.msgs.SceneRecord, at subscribe and per scene
  kStats = 6,       // /rigid/stats        rigid.msgs.StatsRecord, rigidd's Stats
};
inline constexpr std::size_t kChannelCount = 6;
inline std::size_t index_of(Channel c) {
  return static_cast<std::size_t>(c) - 1;
}
std::string_view topic(Channel c);

// Client publish: the one topic a client may advertise, its encoding and schema name. A message
// is a JSON object: {"body": NAME or ID, "force": [x, y, z] (N, in W), "duration": S (s of
// simulated time, (0, kMaxPushDuration]), "point": [x, y, z] (optional: from the centre of mass,
// in B; default 0)}.
inline constexpr std::string_view kPushTopic = "/rigid/push";
inline constexpr std::string_view kPushEncoding = "json";
inline constexpr std::string_view kPushSchemaName = "rigid.Push";
inline constexpr double kMaxPushDuration = 10;
inline constexpr std::size_t kMaxClientChannels = 16;    // a client's advertised channels
inline constexpr std::size_t kMaxClientText = 64 << 10;  // bytes of one client message

// {"op":"serverInfo",...}
std::string server_info_json(bool client_publish, std::string_view session_id);
// {"op":"advertise","channels":[...]}: every Channel (schemas built once).
const std::string& advertise_json();
// {"op":"status","level":L,"message":"..."}: 0 info, 1 warning, 2 error.
std::string status_json(int level, std::string_view message);
// The 13 bytes before a message's payload.
std::array<char, 13> message_data_header(std::uint32_t subscription, std::uint64_t time_ns);

struct Subscribe {
  std::vector<std::pair<std::uint32_t, std::uint32_t>> subscriptions;  // (id, channel id)
};
struct Unsubscribe {
  std::vector<std::uint32_t> ids;
};
struct ClientChannel {
  std::uint32_t id = 0;
  std::string topic, encoding, schema_name;
};
struct ClientAdvertise {
  std::vector<ClientChannel> channels;
};
struct ClientUnadvertise {
  std::vector<std::uint32_t> ids;
};
using ClientText = std::variant<Subscribe, Unsubscribe, ClientAdvertise, ClientUnadvertise>;
// A client's text message, or one line saying why it is refused (not JSON, an unknown op or
// field type, an id that is not a uint32, more than kChannelCount subscriptions or
// kMaxClientChannels channels in one message).
std::variant<ClientText, std::string> parse_client_text(std::string_view text);

struct ClientData {
  std::uint32_t channel = 0;
  std::string_view payload;
};
// A client's binary message: Client Message Data (opcode 0x01), or why it is refused.
std::variant<ClientData, std::string> parse_client_binary(std::string_view bytes);

struct PushRequest {
  std::string body_name;   // when the body is named
  std::int32_t body = -1;  // when it is given by id
  rigid::Vec3 force{};
  rigid::Vec3 point{};
  double duration = 0;
  bool operator==(const PushRequest&) const = default;
};
// A message of kPushTopic (see above), or one line naming the field at fault.
std::variant<PushRequest, std::string> parse_push(std::string_view json);

}  // namespace rigid::view::foxglove
