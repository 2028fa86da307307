// The ROS 2 face's serialization without a network: plain CDR as ROS 2's middlewares write it
// (byte for byte for hand-computed cases), every decoder's refusals, the /tf template against the
// state it is filled from, and ROS names. The independent decoders (node: @foxglove/
// rosmsg2-serialization; Fast DDS) check the same bytes in ros_node_test and ros_fastdds_test.
#include <gtest/gtest.h>

#include <bit>
#include <cstring>
#include <string>
#include <vector>

#include "transport/ros/cdr.hpp"
#include "transport/ros/markers.hpp"
#include "transport/ros/ros_face.hpp"
#include "transport/ros/ros_messages.hpp"
#include "transport/ros/ros_names.hpp"
#include "transport/ros/sim_services.hpp"
#include "transport/ros/tf_message.hpp"

namespace rigid::transport::ros {
namespace {

static_assert(std::endian::native == std::endian::little, "the golden bytes are little endian");

using Bytes = std::vector<std::uint8_t>;

void put32(Bytes& b, std::uint32_t v) {
  for (int i = 0; i < 4; ++i)
    b.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}

TEST(RosCdr, WriterHeaderAlignmentAndStrings) {
  Bytes out{9, 9, 9};  // a reused buffer: cleared
  CdrWriter w(out);
  w.u8(7);
  w.string("ab");  // length 3 (NUL counted), aligned to 4 from the end of the header
  w.f64(1.0);      // aligned to 8 from the end of the header: 1 + 3 + 4 + 3 = 11 -> 16
  const Bytes expected = {0x00, 0x01, 0x00, 0x00,               // CDR_LE
                          7,    0,    0,    0,                  // u8, 3 bytes of padding
                          3,    0,    0,    0,    'a', 'b', 0,  // string
                          0,    0,    0,    0,    0,            // padding to offset 16
                          0,    0,    0,    0,    0,   0,   0xf0, 0x3f};
  EXPECT_EQ(out, expected);
}

TEST(RosCdr, ReaderReadsBothByteOrders) {
  // CDR_BE: int32 -2, uint32 5, a string "x".
  const Bytes be = {0x00, 0x00, 0, 0, 0xff, 0xff, 0xff, 0xfe, 0, 0, 0, 5, 0, 0, 0, 2, 'x', 0};
  CdrReader r(be);
  EXPECT_EQ(r.i32(), -2);
  EXPECT_EQ(r.u32(), 5u);
  std::string s;
  r.string(s, 10);
  EXPECT_TRUE(r.ok());
  EXPECT_EQ(s, "x");
}

TEST(RosCdr, ReaderRefusesWhatIsNotPlainCdr) {
  for (const Bytes& header : {Bytes{0x00, 0x02, 0, 0}, Bytes{0x00, 0x03, 0, 0},
                              Bytes{0x00, 0x07, 0, 0}, Bytes{0x01, 0x01, 0, 0}}) {
    Bytes b = header;
    put32(b, 1);
    CdrReader r(b);
    (void)r.u32();
    EXPECT_EQ(r.status(), DecodeStatus::kMalformed) << int(header[0]) << " " << int(header[1]);
  }
  CdrReader short_one(Bytes{0x00, 0x01});
  EXPECT_EQ(short_one.status(), DecodeStatus::kTruncated);
}

TEST(RosCdr, ReaderStringChecks) {
  const auto read = [](const Bytes& body, std::size_t max) {
    Bytes b = {0x00, 0x01, 0, 0};
    b.insert(b.end(), body.begin(), body.end());
    CdrReader r(b);
    std::string s;
    r.string(s, max);
    return r.status();
  };
  EXPECT_EQ(read({3, 0, 0, 0, 'a', 'b', 0}, 8), DecodeStatus::kOk);
  EXPECT_EQ(read({0, 0, 0, 0}, 8), DecodeStatus::kMalformed);                 // no NUL at all
  EXPECT_EQ(read({3, 0, 0, 0, 'a', 'b', 'c'}, 8), DecodeStatus::kMalformed);  // no terminator
  EXPECT_EQ(read({3, 0, 0, 0, 'a', 0, 0}, 8), DecodeStatus::kMalformed);      // NUL inside
  EXPECT_EQ(read({3, 0, 0, 0, 'a', 'b', 0}, 1), DecodeStatus::kBadCount);     // over the bound
  EXPECT_EQ(read({9, 0, 0, 0, 'a', 0}, 16), DecodeStatus::kTruncated);
  EXPECT_EQ(read({0xff, 0xff, 0xff, 0xff}, 16), DecodeStatus::kBadCount);
}

TEST(RosCdr, ReaderCountIsBoundedByTheBytesLeft) {
  Bytes b = {0x00, 0x01, 0, 0};
  put32(b, 1000);  // 1000 elements of 8 bytes claimed, 8 bytes there
  b.resize(b.size() + 8);
  CdrReader r(b);
  EXPECT_EQ(r.count(1u << 30, 8), 0u);
  EXPECT_EQ(r.status(), DecodeStatus::kBadCount);
  CdrReader r2(b);
  EXPECT_EQ(r2.count(10, 8), 0u);  // over max_count
  EXPECT_EQ(r2.status(), DecodeStatus::kBadCount);
}

TEST(RosMessages, ClockBytes) {
  Bytes out;
  encode_clock(ros_time(12.345), out);
  Bytes expected = {0x00, 0x01, 0x00, 0x00};
  put32(expected, 12);
  put32(expected, 345'000'000);
  EXPECT_EQ(out, expected);
}

TEST(RosMessages, RosTimeRoundsToTheNanosecond) {
  EXPECT_EQ(ros_time(0.0), (RosTime{0, 0}));
  EXPECT_EQ(ros_time(-1.0), (RosTime{0, 0}));
  EXPECT_EQ(ros_time(1.9999999999), (RosTime{2, 0}));
  EXPECT_EQ(ros_time(1234 * 0.001), (RosTime{1, 234'000'000}));
  EXPECT_EQ(ros_time(1e12).sec, 2147483647);
}

Bytes wrench_bytes(bool big_endian, std::string_view frame) {
  Bytes b = {0x00, static_cast<std::uint8_t>(big_endian ? 0 : 1), 0, 0};
  const auto u32 = [&](std::uint32_t v) {
    for (int i = 0; i < 4; ++i)
      b.push_back(static_cast<std::uint8_t>(big_endian ? v >> (24 - 8 * i) : v >> (8 * i)));
  };
  const auto f64 = [&](double d) {
    std::uint64_t v;
    std::memcpy(&v, &d, 8);
    for (int i = 0; i < 8; ++i)
      b.push_back(static_cast<std::uint8_t>(big_endian ? v >> (56 - 8 * i) : v >> (8 * i)));
  };
  u32(7);
  u32(500);
  u32(static_cast<std::uint32_t>(frame.size() + 1));
  b.insert(b.end(), frame.begin(), frame.end());
  b.push_back(0);
  while ((b.size() - 4) % 8 != 0)
    b.push_back(0);
  for (const double v : {1.5, -2.0, 3.25, 0.5, 0.0, -0.125})
    f64(v);
  return b;
}

TEST(RosMessages, WrenchStampedInEitherByteOrder) {
  for (const bool be : {false, true}) {
    WrenchStamped m;
    ASSERT_EQ(decode_wrench_stamped(wrench_bytes(be, "craft"), m), DecodeStatus::kOk);
    EXPECT_EQ(m.stamp, (RosTime{7, 500}));
    EXPECT_EQ(m.frame_id, "craft");
    EXPECT_EQ(m.force, (Vec3{1.5, -2.0, 3.25}));
    EXPECT_EQ(m.torque, (Vec3{0.5, 0.0, -0.125}));
  }
}

TEST(RosMessages, WrenchStampedRefusals) {
  WrenchStamped m;
  Bytes b = wrench_bytes(false, "world");
  for (std::size_t cut = 0; cut < b.size(); ++cut) {
    const Bytes part(b.begin(), b.begin() + static_cast<std::ptrdiff_t>(cut));
    EXPECT_NE(decode_wrench_stamped(part, m), DecodeStatus::kOk) << "cut at " << cut;
  }
  EXPECT_EQ(decode_wrench_stamped(wrench_bytes(false, std::string(kMaxFrameIdLength + 1, 'a')), m),
            DecodeStatus::kBadCount);
  EXPECT_EQ(decode_wrench_stamped(wrench_bytes(false, std::string(kMaxFrameIdLength, 'a')), m),
            DecodeStatus::kOk);
}

TEST(RosMessages, DiscoveryInfoGidSizes) {
  NodeEntities node{"/", "rigidd", {Guid{1}, Guid{2}}, {Guid{3}}};
  Guid me{};
  me[0] = 0xaa;
  me[15] = 0xbb;
  for (const Distro d : {Distro::kHumble, Distro::kJazzy}) {
    const std::size_t gid = d == Distro::kHumble ? 24 : 16;
    Bytes out;
    encode_participant_entities(me, node, d, out);
    CdrReader r(out);
    std::vector<std::uint8_t> first(gid);
    for (auto& x : first)
      x = r.u8();
    EXPECT_EQ(first[0], 0xaa);
    EXPECT_EQ(first[15], 0xbb);
    for (std::size_t i = 16; i < gid; ++i)
      EXPECT_EQ(first[i], 0);
    EXPECT_EQ(r.count(10, 0), 1u);
    std::string ns, name;
    r.string(ns, 256);
    r.string(name, 256);
    EXPECT_EQ(ns, "/");
    EXPECT_EQ(name, "rigidd");
    EXPECT_EQ(r.count(10, 0), 2u);
    r.skip(2 * gid);
    EXPECT_EQ(r.count(10, 0), 1u);
    r.skip(gid);
    EXPECT_TRUE(r.ok());
    EXPECT_EQ(r.remaining(), 0u);
  }
}

StateFrame two_bodies() {
  StateFrame s;
  s.tick = 1234;
  s.sim_time = 1.234;
  s.ids = {0, 1};
  s.position = {1.0, 2.0, 3.0, -4.0, 5.5, 1e-300};
  s.orientation = {0.5, 0.5, 0.5, 0.5, 1.0, 0.0, 0.0, 0.0};
  s.linear_velocity.assign(6, 0.0);
  s.angular_velocity.assign(6, 0.0);
  return s;
}

TEST(RosTf, FilledTemplateCarriesTheStateBitForBit) {
  const std::vector<std::string> names = {"racket", "a/b"};
  TfMessage tf;
  tf.build("world", names);
  const StateFrame s = two_bodies();
  tf.fill(s);
  CdrReader r(tf.bytes());
  ASSERT_EQ(r.count(10, 0), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(r.i32(), 1);
    EXPECT_EQ(r.u32(), 234'000'000u);
    std::string parent, child;
    r.string(parent, 256);
    r.string(child, 256);
    EXPECT_EQ(parent, "world");
    EXPECT_EQ(child, names[i]);
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(std::bit_cast<std::uint64_t>(r.f64()),
                std::bit_cast<std::uint64_t>(s.position[3 * i + k]));
    // x, y, z, w from rigid's w, x, y, z
    for (const int k : {1, 2, 3, 0})
      EXPECT_EQ(std::bit_cast<std::uint64_t>(r.f64()),
                std::bit_cast<std::uint64_t>(s.orientation[4 * i + k]));
  }
  EXPECT_TRUE(r.ok());
  EXPECT_EQ(r.remaining(), 0u);
}

TEST(RosTf, RefillingChangesOnlyStampsAndPoses) {
  TfMessage tf;
  tf.build("world", std::vector<std::string>{"x", "yy"});
  StateFrame s = two_bodies();
  tf.fill(s);
  const Bytes before(tf.bytes().begin(), tf.bytes().end());
  s.sim_time = 2.0;
  s.position[4] = 9.0;
  tf.fill(s);
  const Bytes after(tf.bytes().begin(), tf.bytes().end());
  ASSERT_EQ(before.size(), after.size());
  std::size_t changed = 0;
  for (std::size_t i = 0; i < before.size(); ++i)
    changed += before[i] != after[i] ? 1 : 0;
  // Two stamps (sec 1 -> 2: 1 byte; nanosec: up to 4 bytes each) and one double (<= 8 bytes).
  EXPECT_GT(changed, 0u);
  EXPECT_LE(changed, 2 * 5 + 8u);
}

SceneDescription scene_of(std::vector<ShapeKind> kinds) {
  SceneDescription d;
  for (std::size_t i = 0; i < kinds.size(); ++i) {
    d.ids.push_back(static_cast<std::int32_t>(i));
    d.names.push_back("body" + std::to_string(i));
    d.masses.push_back(1.0);
    for (int k = 0; k < 6; ++k)
      d.inertia.push_back(1.0);
    d.shape_kinds.push_back(kinds[i]);
    d.shape_dims.insert(d.shape_dims.end(), {0.5, 2.0, 3.0});
  }
  return d;
}

// One marker's fields up to its colour, read back.
struct ReadMarker {
  std::string frame, ns;
  std::int32_t id = 0, type = 0, action = 0;
  double pose[7] = {};
  double scale[3] = {};
  float color[4] = {};
};

ReadMarker read_marker(CdrReader& r) {
  ReadMarker m;
  (void)r.i32();
  (void)r.u32();
  r.string(m.frame, 256);
  r.string(m.ns, 256);
  m.id = r.i32();
  m.type = r.i32();
  m.action = r.i32();
  for (double& v : m.pose)
    v = r.f64();
  for (double& v : m.scale)
    v = r.f64();
  for (float& v : m.color)
    v = r.f32();
  (void)r.i32();  // lifetime
  (void)r.u32();
  EXPECT_TRUE(r.boolean());      // frame_locked
  EXPECT_EQ(r.count(0, 0), 0u);  // points
  EXPECT_EQ(r.count(0, 0), 0u);  // colors
  r.skip_string(0);              // texture_resource
  (void)r.i32();                 // texture.header.stamp
  (void)r.u32();
  r.skip_string(0);              // texture.header.frame_id
  r.skip_string(0);              // texture.format
  EXPECT_EQ(r.count(0, 0), 0u);  // texture.data
  EXPECT_EQ(r.count(0, 0), 0u);  // uv_coordinates
  r.skip_string(0);              // text
  r.skip_string(0);              // mesh_resource
  r.skip_string(0);              // mesh_file.filename
  EXPECT_EQ(r.count(0, 0), 0u);  // mesh_file.data
  EXPECT_FALSE(r.boolean());     // mesh_use_embedded_materials
  return m;
}

TEST(RosMarkers, ShapesScalesAndCapsuleEnds) {
  const SceneDescription d =
      scene_of({ShapeKind::kSphere, ShapeKind::kBox, ShapeKind::kCylinder, ShapeKind::kEllipsoid,
                ShapeKind::kCapsule, ShapeKind::kNone});
  Bytes out;
  encode_markers(d, {}, out);
  CdrReader r(out);
  ASSERT_EQ(r.count(100, 0), 8u);  // six bodies, two capsule ends
  const ReadMarker sphere = read_marker(r);
  EXPECT_EQ(sphere.frame, "body0");
  EXPECT_EQ(sphere.type, 2);
  EXPECT_EQ(sphere.scale[0], 1.0);
  EXPECT_EQ(sphere.pose[6], 1.0);  // identity, w last
  const ReadMarker box = read_marker(r);
  EXPECT_EQ(box.type, 1);
  EXPECT_EQ(box.scale[1], 2.0);
  const ReadMarker cylinder = read_marker(r);
  EXPECT_EQ(cylinder.type, 3);
  EXPECT_EQ(cylinder.scale[0], 1.0);
  EXPECT_EQ(cylinder.scale[2], 2.0);
  const ReadMarker ellipsoid = read_marker(r);
  EXPECT_EQ(ellipsoid.type, 2);
  EXPECT_EQ(ellipsoid.scale[2], 6.0);
  const ReadMarker capsule = read_marker(r);
  EXPECT_EQ(capsule.type, 3);
  for (const double z : {1.0, -1.0}) {
    const ReadMarker end = read_marker(r);
    EXPECT_EQ(end.ns, "rigid_capsule_ends");
    EXPECT_EQ(end.frame, "body4");
    EXPECT_EQ(end.type, 2);
    EXPECT_EQ(end.pose[2], z);
    EXPECT_EQ(end.color[0], capsule.color[0]);
  }
  const ReadMarker point = read_marker(r);
  EXPECT_EQ(point.id, 5);
  EXPECT_EQ(point.scale[0], kPointMarkerDiameter);
  // rigid-view's palette: 0x4fc3f7 for the first body.
  EXPECT_FLOAT_EQ(sphere.color[0], 0x4f / 255.0f);
  EXPECT_FLOAT_EQ(sphere.color[3], 1.0f);
  EXPECT_TRUE(r.ok());
  EXPECT_EQ(r.remaining(), 0u);
}

TEST(RosMarkers, PlanBoundsTheLargestSample) {
  Options o;
  SceneDescription d = scene_of(std::vector<ShapeKind>(50, ShapeKind::kCapsule));
  for (auto& n : d.names)
    n = std::string(128, 'n');
  o.body_names = d.names;
  Bytes markers;
  encode_markers(d, {}, markers);
  TfMessage tf;
  tf.build(o.world_frame, o.body_names);
  const Plan p = plan(o);
  EXPECT_GE(p.largest_sample, markers.size());
  EXPECT_GE(p.largest_sample, tf.bytes().size());
}

Bytes request(std::uint64_t client, std::int64_t seq, const std::function<void(CdrWriter&)>& body) {
  Bytes b;
  CdrWriter w(b);
  w.u64(client);
  w.i64(seq);
  body(w);
  return b;
}

TEST(RosServices, RequestsDecode) {
  SimRequest q;
  ASSERT_EQ(decode_request(SimService::kStepSimulation,
                           request(0x1122334455667788ULL, 42, [](CdrWriter& w) { w.u64(10); }), q),
            DecodeStatus::kOk);
  EXPECT_EQ(q.header.client, 0x1122334455667788ULL);
  EXPECT_EQ(q.header.seq, 42);
  EXPECT_EQ(q.steps, 10u);
  ASSERT_EQ(decode_request(SimService::kGetEntityState,
                           request(1, 2, [](CdrWriter& w) { w.string("craft"); }), q),
            DecodeStatus::kOk);
  EXPECT_EQ(q.entity, "craft");
  // GetSimulatorFeatures: ROS 2's one-byte empty request, or nothing at all.
  EXPECT_EQ(decode_request(SimService::kGetSimulatorFeatures,
                           request(1, 3, [](CdrWriter& w) { w.u8(0); }), q),
            DecodeStatus::kOk);
  EXPECT_EQ(decode_request(SimService::kGetSimulatorFeatures, request(1, 3, [](CdrWriter&) {}), q),
            DecodeStatus::kOk);
  // A header alone is not enough for a step.
  EXPECT_EQ(decode_request(SimService::kStepSimulation, request(1, 4, [](CdrWriter&) {}), q),
            DecodeStatus::kTruncated);
}

TEST(RosServices, GetEntitiesFilters) {
  SimRequest q;
  const auto filters = [](std::string name, int categories, int tags, std::uint8_t bounds) {
    return request(5, 6, [&](CdrWriter& w) {
      w.string(name);
      w.count(static_cast<std::size_t>(categories));
      for (int i = 0; i < categories; ++i)
        w.u8(1);
      w.count(static_cast<std::size_t>(tags));
      for (int i = 0; i < tags; ++i)
        w.string("tag");
      w.u8(0);
      w.u8(bounds);
      w.count(0);
    });
  };
  ASSERT_EQ(decode_request(SimService::kGetEntities, filters("^b", 0, 0, 0), q), DecodeStatus::kOk);
  EXPECT_EQ(q.filter, "^b");
  EXPECT_FALSE(q.other_filters);
  ASSERT_EQ(decode_request(SimService::kGetEntities, filters("", 2, 0, 0), q), DecodeStatus::kOk);
  EXPECT_TRUE(q.other_filters);
  ASSERT_EQ(decode_request(SimService::kGetEntities, filters("", 0, 1, 0), q), DecodeStatus::kOk);
  EXPECT_TRUE(q.other_filters);
  ASSERT_EQ(decode_request(SimService::kGetEntities, filters("", 0, 0, 3), q), DecodeStatus::kOk);
  EXPECT_TRUE(q.other_filters);
}

TEST(RosServices, ResponsesEchoTheHeader) {
  Bytes out;
  const RequestHeader h{0xfeedULL, -7};
  EntityState s;
  s.frame_id = "world";
  s.stamp = {3, 4};
  s.position = {1, 2, 3};
  s.orientation_wxyz = {0.5, 0.5, -0.5, 0.5};
  s.linear_velocity = {4, 5, 6};
  s.angular_velocity = {7, 8, 9};
  encode_entity_state_response(h, SimResult::kOk, "", s, out);
  CdrReader r(out);
  EXPECT_EQ(r.u64(), 0xfeedULL);
  EXPECT_EQ(r.i64(), -7);
  EXPECT_EQ(r.u8(), 1);  // RESULT_OK
  r.skip_string(0);
  EXPECT_EQ(r.i32(), 3);
  EXPECT_EQ(r.u32(), 4u);
  std::string frame;
  r.string(frame, 16);
  EXPECT_EQ(frame, "world");
  for (const double v : {1.0, 2.0, 3.0, 0.5, -0.5, 0.5, 0.5, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0})
    EXPECT_EQ(r.f64(), v);
  for (int i = 0; i < 6; ++i)
    EXPECT_EQ(r.f64(), 0.0);
  EXPECT_TRUE(r.ok());
  EXPECT_EQ(r.remaining(), 0u);
}

TEST(RosNames, Namespaces) {
  std::string why;
  EXPECT_EQ(normalize_namespace("", &why), std::string());
  EXPECT_EQ(normalize_namespace("/", &why), std::string());
  EXPECT_EQ(normalize_namespace("lab", &why), std::string("/lab"));
  EXPECT_EQ(normalize_namespace("/lab/arm_2/", &why), std::string("/lab/arm_2"));
  EXPECT_FALSE(normalize_namespace("lab//x", &why));
  EXPECT_NE(why.find("//"), std::string::npos);
  EXPECT_FALSE(normalize_namespace("2lab", &why));
  EXPECT_NE(why.find("digit"), std::string::npos);
  EXPECT_FALSE(normalize_namespace("la-b", &why));
  EXPECT_NE(why.find("'-'"), std::string::npos);
  EXPECT_FALSE(normalize_namespace(std::string(kMaxNamespaceLength + 1, 'a'), &why));
}

TEST(RosNames, BodiesWithoutAWrenchTopic) {
  Options o;
  o.body_names = {"craft", "arm/link_1", "my.box", "2fast", "a-b", "_ok", std::string(128, 'x')};
  const Plan p = plan(o);
  EXPECT_EQ(p.wrench_topics, 4u);  // craft, arm/link_1, _ok, the long one
  ASSERT_EQ(p.notes.size(), 3u);
  EXPECT_NE(p.notes[0].find("my.box"), std::string::npos);
  o.ns = "/" + std::string(kMaxNamespaceLength - 1, 'n');
  EXPECT_EQ(plan(o).wrench_topics, 4u);  // the longest namespace still leaves room
}

TEST(RosNames, DdsNames) {
  EXPECT_EQ(dds_topic("/tf"), "rt/tf");
  EXPECT_EQ(dds_request_topic("/rigidd/step_simulation"), "rq/rigidd/step_simulationRequest");
  EXPECT_EQ(dds_reply_topic("/rigidd/step_simulation"), "rr/rigidd/step_simulationReply");
  EXPECT_EQ(dds_message_type("tf2_msgs", "TFMessage"), "tf2_msgs::msg::dds_::TFMessage_");
  EXPECT_EQ(dds_request_type("simulation_interfaces", "StepSimulation"),
            "simulation_interfaces::srv::dds_::StepSimulation_Request_");
  EXPECT_EQ(dds_response_type("simulation_interfaces", "StepSimulation"),
            "simulation_interfaces::srv::dds_::StepSimulation_Response_");
}

}  // namespace
}  // namespace rigid::transport::ros
