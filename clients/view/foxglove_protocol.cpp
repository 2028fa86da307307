#include "foxglove_protocol.hpp"

#include <cmath>
#include <cstdio>
#include <cstring>

#include "common/foxglove_messages.hpp"
#include "foxglove/FrameTransforms.pb.h"
#include "foxglove/SceneUpdate.pb.h"
#include "json_value.hpp"
#include "live/body_states.pb.h"
#include "protocol.hpp"
#include "rigid.pb.h"

namespace rigid::view::foxglove {
namespace {

void json_string(std::string& out, std::string_view s) {
  out += '"';
  for (const char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (u < 0x20) {
      char b[8];
      std::snprintf(b, sizeof b, "\\u%04x", u);
      out += b;
    } else {
      out += c;
    }
  }
  out += '"';
}

// RFC 4648 base64 (the advertised schemas are binary FileDescriptorSets).
std::string base64(std::string_view in) {
  static constexpr char kDigits[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((in.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 3 <= in.size(); i += 3) {
    const std::uint32_t v = static_cast<std::uint32_t>(static_cast<unsigned char>(in[i])) << 16 |
                            static_cast<std::uint32_t>(static_cast<unsigned char>(in[i + 1])) << 8 |
                            static_cast<unsigned char>(in[i + 2]);
    out += kDigits[v >> 18];
    out += kDigits[(v >> 12) & 63];
    out += kDigits[(v >> 6) & 63];
    out += kDigits[v & 63];
  }
  if (const std::size_t rest = in.size() - i; rest > 0) {
    std::uint32_t v = static_cast<std::uint32_t>(static_cast<unsigned char>(in[i])) << 16;
    if (rest == 2) v |= static_cast<std::uint32_t>(static_cast<unsigned char>(in[i + 1])) << 8;
    out += kDigits[v >> 18];
    out += kDigits[(v >> 12) & 63];
    out += rest == 2 ? kDigits[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

struct ChannelSpec {
  Channel channel;
  std::string_view topic;
  const google::protobuf::Descriptor* (*descriptor)();
};
const std::array<ChannelSpec, kChannelCount>& specs() {
  static const std::array<ChannelSpec, kChannelCount> kSpecs{{
      {Channel::kTransforms, "/rigid/transforms", &::foxglove::FrameTransforms::descriptor},
      {Channel::kBodies, "/rigid/bodies", &::foxglove::SceneUpdate::descriptor},
      {Channel::kBodyStates, "/rigid/body_states", &rigid::msgs::BodyStates::descriptor},
      {Channel::kState, "/rigid/state", &rigid::msgs::StateRecord::descriptor},
      {Channel::kScene, "/rigid/scene", &rigid::msgs::SceneRecord::descriptor},
      {Channel::kStats, "/rigid/stats", &rigid::msgs::StatsRecord::descriptor},
  }};
  return kSpecs;
}

// A uint32 id of a client message: a whole number in [0, 2^32).
bool uint32_of(const Json* v, std::uint32_t& out) {
  if (v == nullptr || v->kind != Json::Kind::kNumber || !(v->number >= 0) ||
      v->number > 4294967295.0 || std::floor(v->number) != v->number)
    return false;
  out = static_cast<std::uint32_t>(v->number);
  return true;
}

std::string text_of(const Json* v, std::string_view field, std::string& out) {
  if (v == nullptr || v->kind != Json::Kind::kString)
    return std::string(field) + ": expected a string";
  if (v->text.size() > 256) return std::string(field) + ": longer than 256 bytes";
  out = v->text;
  return {};
}

// [x, y, z] of finite numbers each at most `limit` in magnitude.
std::string vec3_of(const Json* v, std::string_view field, double limit, rigid::Vec3& out) {
  if (v == nullptr || v->kind != Json::Kind::kArray || v->items.size() != 3)
    return std::string(field) + ": expected [x, y, z]";
  for (std::size_t k = 0; k < 3; ++k) {
    if (v->items[k].kind != Json::Kind::kNumber || !(std::abs(v->items[k].number) <= limit)) {
      char b[32];
      std::snprintf(b, sizeof b, "%g", limit);
      return std::string(field) + ": expected numbers of magnitude at most " + b;
    }
    out[k] = v->items[k].number;
  }
  return {};
}

}  // namespace

std::string_view topic(Channel c) {
  return specs()[index_of(c)].topic;
}

std::string server_info_json(bool client_publish, std::string_view session_id) {
  std::string out = R"({"op":"serverInfo","name":"rigid-view","capabilities":[)";
  if (client_publish)
    out += R"("clientPublish"],"supportedEncodings":["json"])";
  else
    out += "]";
  out += R"(,"metadata":{"push_topic":)";
  json_string(out, kPushTopic);
  out += R"(},"sessionId":)";
  json_string(out, session_id);
  out += '}';
  return out;
}

const std::string& advertise_json() {
  static const std::string kText = [] {
    std::string out = R"({"op":"advertise","channels":[)";
    bool first = true;
    for (const ChannelSpec& s : specs()) {
      if (!first) out += ',';
      first = false;
      out += R"({"id":)";
      out += std::to_string(static_cast<std::uint32_t>(s.channel));
      out += R"(,"topic":)";
      json_string(out, s.topic);
      out += R"(,"encoding":"protobuf","schemaName":)";
      json_string(out, s.descriptor()->full_name());
      out += R"(,"schemaEncoding":"protobuf","schema":")";
      out += base64(common::foxglove::descriptor_set(s.descriptor()));
      out += "\"}";
    }
    out += "]}";
    return out;
  }();
  return kText;
}

std::string status_json(int level, std::string_view message) {
  std::string out = R"({"op":"status","level":)";
  out += std::to_string(level);
  out += R"(,"message":)";
  json_string(out, message);
  out += '}';
  return out;
}

std::array<char, 13> message_data_header(std::uint32_t subscription, std::uint64_t time_ns) {
  // Little-endian, as the hosts rigid runs on are (x86-64, aarch64).
  std::array<char, 13> h{};
  h[0] = 0x01;
  std::memcpy(h.data() + 1, &subscription, 4);
  std::memcpy(h.data() + 5, &time_ns, 8);
  return h;
}

std::variant<ClientText, std::string> parse_client_text(std::string_view text) {
  auto parsed = parse_json(text);
  if (auto* error = std::get_if<std::string>(&parsed)) return std::move(*error);
  const Json& j = std::get<Json>(parsed);
  if (j.kind != Json::Kind::kObject) return std::string("expected a JSON object");
  const Json* op = j.get("op");
  if (op == nullptr || op->kind != Json::Kind::kString) return std::string("op: expected a string");
  const auto array_of = [&](std::string_view field, std::size_t max) -> const Json* {
    const Json* a = j.get(field);
    if (a == nullptr || a->kind != Json::Kind::kArray || a->items.size() > max) return nullptr;
    return a;
  };
  if (op->text == "subscribe") {
    const Json* a = array_of("subscriptions", kChannelCount);
    if (a == nullptr)
      return "subscribe: subscriptions: expected an array of at most " +
             std::to_string(kChannelCount);
    Subscribe s;
    for (const Json& e : a->items) {
      std::uint32_t id = 0, channel = 0;
      if (e.kind != Json::Kind::kObject || !uint32_of(e.get("id"), id) ||
          !uint32_of(e.get("channelId"), channel))
        return std::string("subscribe: each subscription needs id and channelId (uint32)");
      s.subscriptions.emplace_back(id, channel);
    }
    return ClientText{std::move(s)};
  }
  if (op->text == "unsubscribe" || op->text == "unadvertise") {
    const bool subs = op->text == "unsubscribe";
    const Json* a = array_of(subs ? "subscriptionIds" : "channelIds",
                             subs ? kChannelCount : kMaxClientChannels);
    std::vector<std::uint32_t> ids;
    for (std::size_t k = 0; a != nullptr && k < a->items.size(); ++k) {
      std::uint32_t id = 0;
      if (!uint32_of(&a->items[k], id)) {
        a = nullptr;
        break;
      }
      ids.push_back(id);
    }
    if (a == nullptr) {
      return subs ? "unsubscribe: subscriptionIds: expected at most " +
                        std::to_string(kChannelCount) + " uint32"
                  : "unadvertise: channelIds: expected at most " +
                        std::to_string(kMaxClientChannels) + " uint32";
    }
    if (subs) return ClientText{Unsubscribe{std::move(ids)}};
    return ClientText{ClientUnadvertise{std::move(ids)}};
  }
  if (op->text == "advertise") {
    const Json* a = array_of("channels", kMaxClientChannels);
    if (a == nullptr)
      return "advertise: channels: expected an array of at most " +
             std::to_string(kMaxClientChannels);
    ClientAdvertise adv;
    for (const Json& e : a->items) {
      ClientChannel c;
      if (e.kind != Json::Kind::kObject || !uint32_of(e.get("id"), c.id))
        return std::string("advertise: each channel needs an id (uint32)");
      for (auto [field, out] : {std::pair<std::string_view, std::string*>{"topic", &c.topic},
                                {"encoding", &c.encoding},
                                {"schemaName", &c.schema_name}}) {
        if (std::string e2 = text_of(e.get(field), field, *out); !e2.empty())
          return "advertise: " + e2;
      }
      adv.channels.push_back(std::move(c));
    }
    return ClientText{std::move(adv)};
  }
  return "unknown op " + op->text.substr(0, 40) + " (rigid-view serves subscribe, unsubscribe" +
         ", advertise, unadvertise)";
}

std::variant<ClientData, std::string> parse_client_binary(std::string_view bytes) {
  if (bytes.empty() || bytes[0] != 0x01)
    return std::string("binary message: only Client Message Data (opcode 0x01) is served");
  if (bytes.size() < 5) return std::string("Client Message Data shorter than its 5-byte header");
  ClientData d;
  std::memcpy(&d.channel, bytes.data() + 1, 4);
  d.payload = bytes.substr(5);
  return d;
}

std::variant<PushRequest, std::string> parse_push(std::string_view json) {
  auto parsed = parse_json(json);
  if (auto* error = std::get_if<std::string>(&parsed))
    return std::string(kPushTopic) + ": " + *error;
  const Json& j = std::get<Json>(parsed);
  const std::string where = std::string(kPushTopic) + ": ";
  if (j.kind != Json::Kind::kObject) return where + "expected a JSON object";
  PushRequest p;
  bool have_body = false, have_force = false, have_duration = false;
  for (const auto& [key, v] : j.fields) {  // (JsonField: key, value)
    // One value per field: with "body" given both as a name and as an id, which one is meant?
    if (j.get(key) != &v) return where + key.substr(0, 40) + ": given twice";
    if (key == "body") {
      if (v.kind == Json::Kind::kString && !v.text.empty() && v.text.size() <= 256) {
        p.body_name = v.text;
      } else if (v.kind == Json::Kind::kNumber && v.number >= 0 && v.number <= 2147483647.0 &&
                 std::floor(v.number) == v.number) {
        p.body = static_cast<std::int32_t>(v.number);
      } else {
        return where + "body: expected a body's name or id";
      }
      have_body = true;
    } else if (key == "force") {
      if (std::string e = vec3_of(&v, "force", kMaxPushForce, p.force); !e.empty())
        return where + e;
      have_force = true;
    } else if (key == "point") {
      if (std::string e = vec3_of(&v, "point", kMaxPushPoint, p.point); !e.empty())
        return where + e;
    } else if (key == "duration") {
      if (v.kind != Json::Kind::kNumber || !(v.number > 0 && v.number <= kMaxPushDuration))
        return where + "duration: expected seconds in (0, 10]";
      p.duration = v.number;
      have_duration = true;
    } else {
      return where + "unknown field " + key.substr(0, 40) +
             " (body, force, duration and point are read)";
    }
  }
  if (!have_body || !have_force || !have_duration) return where + "needs body, force and duration";
  return p;
}

}  // namespace rigid::view::foxglove
