// rigid-view's Foxglove protocol as pure functions (clients/view/foxglove_protocol.hpp,
// json_value.hpp): the client's messages checked field by field, the JSON reader's bounds, the
// Message Data header, the advertised channels, and the shared encoders' bytes decoded back with
// the generated protobuf classes (common/foxglove_messages.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "common/foxglove_messages.hpp"
#include "foxglove/FrameTransforms.pb.h"
#include "foxglove/SceneUpdate.pb.h"
#include "foxglove_protocol.hpp"
#include "json_value.hpp"
#include "live/body_states.pb.h"

namespace rigid::view {
namespace {

namespace fx = foxglove;

std::string error_of(const std::variant<Json, std::string>& v) {
  return std::holds_alternative<std::string>(v) ? std::get<std::string>(v) : "";
}

TEST(FoxgloveJson, ReadsNestedValuesAndEscapes) {
  auto v =
      parse_json(R"( {"a":[1,-2.5e3,{"b":null}],"s":"x\"\\\/\n\u00e9\ud83d\ude00","t":true} )");
  ASSERT_TRUE(std::holds_alternative<Json>(v)) << error_of(v);
  const Json& j = std::get<Json>(v);
  ASSERT_EQ(j.get("a")->items.size(), 3u);
  EXPECT_EQ(j.get("a")->items[1].number, -2500);
  EXPECT_EQ(j.get("a")->items[2].get("b")->kind, Json::Kind::kNull);
  EXPECT_EQ(j.get("s")->text, "x\"\\/\n\xc3\xa9\xf0\x9f\x98\x80");
  EXPECT_TRUE(j.get("t")->boolean);
  EXPECT_EQ(j.get("missing"), nullptr);
}

TEST(FoxgloveJson, RefusesWhatIsNotJsonOrBeyondTheBounds) {
  for (const char* bad : {"", "{", "{\"a\":}", "[1,]", "01", "1.", "-", "\"a", "\"\\x\"",
                          "\"\\ud800\"", "{\"a\":1}x", "nul", "1e999", "\"\x01\""}) {
    EXPECT_FALSE(error_of(parse_json(bad)).empty()) << bad;
  }
  EXPECT_NE(error_of(parse_json(std::string(9, '[') + std::string(9, ']'))).find("deeper"),
            std::string::npos);
  EXPECT_TRUE(error_of(parse_json(std::string(8, '[') + std::string(8, ']'))).empty());
  std::string many = "[";
  for (std::size_t i = 0; i < kMaxJsonValues; ++i)
    many += i ? ",0" : "0";
  EXPECT_NE(error_of(parse_json(many + "]")).find("values"), std::string::npos);
}

TEST(FoxgloveProtocol, ParsesSubscribeAndUnsubscribe) {
  auto v = fx::parse_client_text(
      R"({"op":"subscribe","subscriptions":[{"id":0,"channelId":1},{"id":7,"channelId":3}]})");
  ASSERT_TRUE(std::holds_alternative<fx::ClientText>(v));
  const auto& s = std::get<fx::Subscribe>(std::get<fx::ClientText>(v));
  ASSERT_EQ(s.subscriptions.size(), 2u);
  EXPECT_EQ(s.subscriptions[1], (std::pair<std::uint32_t, std::uint32_t>{7, 3}));
  auto u = fx::parse_client_text(R"({"op":"unsubscribe","subscriptionIds":[7,4294967295]})");
  ASSERT_TRUE(std::holds_alternative<fx::ClientText>(u));
  EXPECT_EQ(std::get<fx::Unsubscribe>(std::get<fx::ClientText>(u)).ids,
            (std::vector<std::uint32_t>{7, 4294967295u}));
}

TEST(FoxgloveProtocol, RefusesBadClientTexts) {
  const std::pair<const char*, const char*> cases[] = {
      {"[]", "expected a JSON object"},
      {R"({"op":1})", "op: expected a string"},
      {R"({"op":"getParameters"})", "unknown op getParameters"},
      {R"({"op":"subscribe","subscriptions":[{"id":-1,"channelId":1}]})", "id and channelId"},
      {R"({"op":"subscribe","subscriptions":[{"id":1.5,"channelId":1}]})", "id and channelId"},
      {R"({"op":"subscribe","subscriptions":[{"id":4294967296,"channelId":1}]})",
       "id and channelId"},
      {R"({"op":"subscribe","subscriptions":[{},{},{},{},{},{},{}]})", "at most 6"},
      {R"({"op":"unsubscribe","subscriptionIds":["a"]})", "subscriptionIds"},
      {R"({"op":"advertise","channels":[{"id":1,"topic":"/rigid/push","encoding":"json"}]})",
       "schemaName: expected a string"},
      {R"({"op":"unadvertise"})", "channelIds"},
  };
  for (const auto& [text, why] : cases) {
    auto v = fx::parse_client_text(text);
    ASSERT_TRUE(std::holds_alternative<std::string>(v)) << text;
    EXPECT_NE(std::get<std::string>(v).find(why), std::string::npos)
        << text << " -> " << std::get<std::string>(v);
  }
}

TEST(FoxgloveProtocol, ParsesClientBinaryAndPush) {
  std::string bytes = "\x01";
  const std::uint32_t channel = 0x01020304;
  bytes.append(reinterpret_cast<const char*>(&channel), 4);
  bytes += "{}";
  auto d = fx::parse_client_binary(bytes);
  ASSERT_TRUE(std::holds_alternative<fx::ClientData>(d));
  EXPECT_EQ(std::get<fx::ClientData>(d).channel, channel);
  EXPECT_EQ(std::get<fx::ClientData>(d).payload, "{}");
  EXPECT_TRUE(std::holds_alternative<std::string>(fx::parse_client_binary("\x01\x00\x00")));
  EXPECT_TRUE(std::holds_alternative<std::string>(fx::parse_client_binary("\x02\x00\x00\x00\x00")));

  auto p = fx::parse_push(R"({"body":"ball","force":[0,0,10],"duration":0.5})");
  ASSERT_TRUE(std::holds_alternative<fx::PushRequest>(p));
  fx::PushRequest want;
  want.body_name = "ball";
  want.force = {0, 0, 10};
  want.duration = 0.5;
  EXPECT_EQ(std::get<fx::PushRequest>(p), want);
  auto q = fx::parse_push(R"({"body":3,"force":[1,2,3],"duration":10,"point":[0,0.1,0]})");
  ASSERT_TRUE(std::holds_alternative<fx::PushRequest>(q));
  EXPECT_EQ(std::get<fx::PushRequest>(q).body, 3);
  EXPECT_EQ(std::get<fx::PushRequest>(q).point[1], 0.1);
  const std::pair<const char*, const char*> bad[] = {
      {R"({"body":"ball","force":[0,0,10]})", "needs body, force and duration"},
      {R"({"body":"","force":[0,0,1],"duration":1})", "body:"},
      {R"({"body":-1,"force":[0,0,1],"duration":1})", "body:"},
      {R"({"body":"b","force":[0,0,1e5],"duration":1})", "force:"},
      {R"({"body":"b","force":[0,0,"1"],"duration":1})", "force:"},
      {R"({"body":"b","force":[0,0,1],"duration":0})", "duration:"},
      {R"({"body":"b","force":[0,0,1],"duration":10.5})", "duration:"},
      {R"({"body":"b","force":[0,0,1],"duration":1,"point":[0,0,101]})", "point:"},
      {R"({"body":"b","force":[0,0,1],"duration":1,"ttl":1})", "unknown field ttl"},
      {R"({"body":"b","body":3,"force":[0,0,1],"duration":1})", "body: given twice"},
      {R"({"body":"b","force":[0,0,1],"duration":1,"duration":2})", "duration: given twice"},
      {"not json", "JSON:"},
  };
  for (const auto& [text, why] : bad) {
    auto v = fx::parse_push(text);
    ASSERT_TRUE(std::holds_alternative<std::string>(v)) << text;
    EXPECT_NE(std::get<std::string>(v).find(why), std::string::npos)
        << text << " -> " << std::get<std::string>(v);
  }
}

TEST(FoxgloveProtocol, ServerTexts) {
  EXPECT_NE(fx::server_info_json(true, "1").find(R"("capabilities":["clientPublish"],)"
                                                 R"("supportedEncodings":["json"])"),
            std::string::npos);
  EXPECT_NE(fx::server_info_json(false, "1").find(R"("capabilities":[],)"), std::string::npos);
  EXPECT_EQ(fx::server_info_json(false, "1").find("supportedEncodings"), std::string::npos);
  const std::string& adv = fx::advertise_json();
  for (const char* topic : {"/rigid/transforms", "/rigid/bodies", "/rigid/body_states",
                            "/rigid/state", "/rigid/scene", "/rigid/stats"})
    EXPECT_NE(adv.find(std::string("\"topic\":\"") + topic + "\""), std::string::npos) << topic;
  EXPECT_NE(adv.find(R"("id":1,"topic":"/rigid/transforms","encoding":"protobuf",)"
                     R"("schemaName":"foxglove.FrameTransforms","schemaEncoding":"protobuf")"),
            std::string::npos);
  EXPECT_EQ(fx::status_json(2, "a \"b\"\n"),
            R"({"op":"status","level":2,"message":"a \"b\"\u000a"})");
  const auto h = fx::message_data_header(0x0a0b0c0d, 0x0102030405060708ull);
  const unsigned char want[13] = {1, 0x0d, 0x0c, 0x0b, 0x0a, 8, 7, 6, 5, 4, 3, 2, 1};
  EXPECT_EQ(std::memcmp(h.data(), want, 13), 0);
}

TEST(FoxgloveMessages, EncodersDecodeWithTheSchemas) {
  StateFrame s;
  s.tick = -3;  // an int64 below zero, as a varint of ten bytes
  s.sim_time = 1.25;
  s.stamp_ns = 1'700'000'000'123'456'789;
  s.ids = {4, -1};
  s.position = {1, -0.0, 3e-300, 4, 5, 6};
  s.orientation = {0.5, 0.5, -0.5, 0.5, 1, 0, 0, 0};
  s.linear_velocity = {7, 8, 9, 10, 11, 12};
  s.angular_velocity = {13, 14, 15, 16, 17, 18};
  const std::vector<std::string> names{"ball", std::string(200, 'n')};
  std::string bytes;
  common::foxglove::append_body_states(bytes, s, names);
  rigid::msgs::BodyStates b;
  ASSERT_TRUE(b.ParseFromString(bytes));
  EXPECT_EQ(b.tick(), -3);
  EXPECT_EQ(b.sim_time(), 1.25);
  EXPECT_EQ(b.timestamp().seconds(), 1'700'000'000);
  EXPECT_EQ(b.timestamp().nanos(), 123'456'789);
  ASSERT_EQ(b.bodies_size(), 2);
  EXPECT_EQ(b.bodies(1).name(), names[1]);
  EXPECT_EQ(b.bodies(1).id(), -1);
  EXPECT_EQ(b.bodies(0).position().z(), 3e-300);
  EXPECT_TRUE(std::signbit(b.bodies(0).position().y()));
  EXPECT_EQ(b.bodies(0).orientation().w(), 0.5);
  EXPECT_EQ(b.bodies(0).orientation().y(), -0.5);
  EXPECT_EQ(b.bodies(1).linear_velocity().z(), 12);
  EXPECT_EQ(b.bodies(1).angular_velocity().x(), 16);

  std::string tf;
  common::foxglove::append_frame_transforms(tf, names, s.position.data(), s.orientation.data(), 42);
  ::foxglove::FrameTransforms t;
  ASSERT_TRUE(t.ParseFromString(tf));
  ASSERT_EQ(t.transforms_size(), 2);
  EXPECT_EQ(t.transforms(1).child_frame_id(), names[1]);
  EXPECT_EQ(t.transforms(0).parent_frame_id(), "world");
  EXPECT_EQ(t.transforms(0).timestamp().nanos(), 42);
  EXPECT_EQ(t.transforms(1).translation().x(), 4);
  EXPECT_EQ(t.transforms(1).rotation().w(), 1);

  SceneDescription scene;
  scene.ids = {4};
  scene.names = {"ball"};
  scene.masses = {2};
  scene.inertia = {1, 1, 1, 0, 0, 0};
  scene.shape_kinds = {ShapeKind::kSphere};
  scene.shape_dims = {0.25, 0, 0};
  ASSERT_TRUE(scene.lengths_agree());
  ::foxglove::SceneUpdate u;
  ASSERT_TRUE(u.ParseFromString(common::foxglove::scene_update(scene, 7, true)));
  ASSERT_EQ(u.deletions_size(), 1);
  EXPECT_EQ(u.deletions(0).type(), ::foxglove::SceneEntityDeletion::ALL);
  ASSERT_EQ(u.entities_size(), 1);
  EXPECT_EQ(u.entities(0).spheres(0).size().x(), 0.5);
  ASSERT_TRUE(u.ParseFromString(common::foxglove::scene_update(scene, 7, false)));
  EXPECT_EQ(u.deletions_size(), 0);
}

}  // namespace
}  // namespace rigid::view
