// rigid-view's WebSocket protocol: the page's commands checked (garbage, huge, unknown refused with
// a reason) and the binary state frame laid out as the page reads it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "protocol.hpp"
#include "view_options.hpp"

namespace rigid::view {
namespace {

std::string refusal(std::string_view text) {
  auto r = parse_command(text);
  return std::holds_alternative<std::string>(r) ? std::get<std::string>(r) : std::string();
}

TEST(ViewProtocol, AcceptsTheControls) {
  auto r = parse_command(R"({"op":"pause","id":7})");
  ASSERT_TRUE(std::holds_alternative<PageCommand>(r));
  EXPECT_EQ(std::get<PageCommand>(r).op, Op::kPause);
  EXPECT_EQ(std::get<PageCommand>(r).id, 7);
  r = parse_command(R"( { "op" : "step", "id": 1, "steps": 25 } )");
  ASSERT_TRUE(std::holds_alternative<PageCommand>(r));
  EXPECT_EQ(std::get<PageCommand>(r).steps, 25);
  r = parse_command(R"({"op":"push","body":3,"force":[1,-2.5,3e1],"point":[0,0,0.1]})");
  ASSERT_TRUE(std::holds_alternative<PageCommand>(r));
  const PageCommand c = std::get<PageCommand>(r);
  EXPECT_EQ(c.body, 3);
  EXPECT_EQ(c.force, (rigid::Vec3{1, -2.5, 30}));
  EXPECT_EQ(c.point, (rigid::Vec3{0, 0, 0.1}));
}

// rigidd's edits from the page: set_state with the parts given (world frame), reset_body.
TEST(ViewProtocol, AcceptsTheEdits) {
  auto r = parse_command(
      R"({"op":"set_state","id":4,"body":2,"position":[1,2,3],"orientation":[0.5,0.5,-0.5,0.5],)"
      R"("angular_velocity":[0,0,-7]})");
  ASSERT_TRUE(std::holds_alternative<PageCommand>(r)) << std::get<std::string>(r);
  PageCommand c = std::get<PageCommand>(r);
  EXPECT_EQ(c.op, Op::kSetState);
  EXPECT_EQ(c.id, 4);
  EXPECT_EQ(c.body, 2);
  EXPECT_EQ(c.state.set, rigid::kSetPosition | rigid::kSetOrientation | rigid::kSetAngularVelocity);
  EXPECT_EQ(c.state.position, (rigid::Vec3{1, 2, 3}));
  EXPECT_EQ(c.state.orientation, (std::array<double, 4>{0.5, 0.5, -0.5, 0.5}));
  EXPECT_EQ(c.state.angular_velocity, (rigid::Vec3{0, 0, -7}));
  EXPECT_EQ(c.state.linear_velocity, (rigid::Vec3{}));
  EXPECT_EQ(c.state.velocity_frame, rigid::Frame::kWorld);
  r = parse_command(R"({"op":"set_state","id":5,"body":0,"velocity":[0,0,0]})");
  ASSERT_TRUE(std::holds_alternative<PageCommand>(r));
  EXPECT_EQ(std::get<PageCommand>(r).state.set, rigid::kSetLinearVelocity);
  r = parse_command(R"({"op":"reset_body","id":6,"body":1})");
  ASSERT_TRUE(std::holds_alternative<PageCommand>(r));
  EXPECT_EQ(std::get<PageCommand>(r).op, Op::kResetBody);
  EXPECT_EQ(std::get<PageCommand>(r).body, 1);
  EXPECT_EQ(op_name(Op::kSetState), "set_state");
  EXPECT_EQ(op_name(Op::kResetBody), "reset_body");

  EXPECT_EQ(refusal(R"({"op":"set_state","id":1,"body":1})"),
            "set_state: needs one of position, orientation, velocity, angular_velocity");
  EXPECT_EQ(refusal(R"({"op":"set_state","id":1,"position":[0,0,0]})"), "set_state: missing body");
  EXPECT_EQ(refusal(R"({"op":"set_state","body":1,"position":[0,0,0]})"), "set_state: missing id");
  EXPECT_EQ(refusal(R"({"op":"set_state","id":1,"body":1,"position":[0,0]})"),
            "position: expected [x, y, z]");
  EXPECT_EQ(refusal(R"({"op":"set_state","id":1,"body":1,"orientation":[1,0,0]})"),
            "orientation: expected [w, x, y, z]");
  EXPECT_EQ(refusal(R"({"op":"set_state","id":1,"body":1,"orientation":[2,0,0,0]})"),
            "orientation: component beyond 1.01");
  EXPECT_EQ(refusal(R"({"op":"set_state","id":1,"body":1,"velocity":[2e9,0,0]})"),
            "velocity: component beyond 1e9");
  EXPECT_EQ(refusal(R"({"op":"set_state","id":1,"body":1,"velocity":[0,0,0],"steps":3})"),
            "set_state: unexpected field");
  EXPECT_EQ(refusal(R"({"op":"reset_body","id":1,"body":1,"position":[0,0,0]})"),
            "reset_body: unexpected field");
  EXPECT_EQ(refusal(R"({"op":"pause","id":1,"position":[0,0,0]})"), "pause: unexpected field");
  EXPECT_EQ(refusal(R"({"op":"push","body":1,"force":[1,0,0],"point":[0,0,0],"velocity":[0,0,0]})"),
            "push: unexpected field");
  // rigidd has nothing to edit while a recording plays; a read-only page is refused by the server.
  EXPECT_NE(refusal_in_mode(c, true), "");
  EXPECT_EQ(refusal_in_mode(c, false), "");
}

TEST(ViewProtocol, RefusesGarbageWithAReason) {
  EXPECT_EQ(refusal(""), "expected a JSON object");
  EXPECT_EQ(refusal("\x01\xff garbage"), "expected a JSON object");
  EXPECT_EQ(refusal(R"({"op":"pause","id":1} x)"), "trailing bytes after the object");
  EXPECT_EQ(refusal(R"({"op":"pause","id":1)"), "expected ',' or '}'");
  EXPECT_EQ(refusal(R"({"op":"launch","id":1})"), "unknown op launch");
  EXPECT_EQ(refusal(R"({"op":"pause","id":1,"evil":2})"), "unknown field evil");
  EXPECT_EQ(refusal(R"({"op":"pause"})"), "pause: missing id");
  EXPECT_EQ(refusal(R"({"op":"step","id":1})"), "step: missing steps");
  EXPECT_EQ(refusal(R"({"op":"step","id":1,"steps":0})"),
            "steps: expected an integer in [1, 1000000]");
  EXPECT_EQ(refusal(R"({"op":"step","id":1,"steps":1.5})"),
            "steps: expected an integer in [1, 1000000]");
  EXPECT_EQ(refusal(R"({"op":"pause","id":-1})"), "id: expected an integer in [0, 2^53]");
  EXPECT_EQ(refusal(R"({"op":"pause","id":1e400})"), "bad value of id");
  EXPECT_EQ(refusal(R"({"op":"pa\"use","id":1})"), "bad string");
  EXPECT_EQ(refusal(R"({"op":"push","body":1,"force":[1,2],"point":[0,0,0]})"),
            "force: expected [x, y, z]");
  EXPECT_EQ(refusal(R"({"op":"push","body":1,"force":[1,2,3,4],"point":[0,0,0]})"),
            "force: expected [x, y, z]");
  EXPECT_EQ(refusal(R"({"op":"push","body":1,"force":[1,2,3,4,5],"point":[0,0,0]})"),
            "bad array (at most 4 numbers)");
  EXPECT_EQ(refusal(R"({"op":"push","body":1,"force":[1e5,0,0],"point":[0,0,0]})"),
            "force: component beyond 1e4");
  EXPECT_EQ(refusal(R"({"op":"push","body":1,"force":[1,0,0]})"),
            "push: needs body, force and point");
  EXPECT_EQ(refusal(R"({"op":"pause","id":1,"steps":2})"), "pause: unexpected field");
  EXPECT_EQ(refusal(R"({"id":1,"id":1,"id":1,"id":1,"id":1,"id":1,"id":1,"id":1,"id":1})"),
            "too many fields");
  EXPECT_EQ(refusal(R"({"op":{"nested":1}})"), "bad value of op");
  EXPECT_EQ(refusal(std::string(600, ' ')), "command longer than 512 bytes");
}

TEST(ViewProtocol, StateFrameLayout) {
  StateFrame s;
  s.resize(2);
  s.tick = 1234;
  s.sim_time = 1.234;
  s.stamp_ns = 1'700'000'000'123'456'789;
  s.ids = {5, 9};
  s.position = {1, 2, 3, 4, 5, 6};
  s.orientation = {1, 0, 0, 0, 0.5, 0.5, 0.5, 0.5};
  s.linear_velocity = {-1, -2, -3, -4, -5, -6};
  s.angular_velocity = {10, 20, 30, 40, 50, 60.000000000000007};
  const std::string f = encode_state(s, 3, {1e-12f, 2.5f}, {0.25f, 3e-9f});
  ASSERT_EQ(f.size(), kStateHeaderBytes + 2 * (13 * 8 + 2 * 4 + 4));
  ASSERT_EQ(f.size(), kStateHeaderBytes + 2 * state_bytes_per_body(2));
  std::uint32_t u[4];
  std::memcpy(u, f.data(), 16);
  EXPECT_EQ(u[0], kStateMagic);
  EXPECT_EQ(u[1], 2u);
  EXPECT_EQ(u[2], 3u);
  EXPECT_EQ(u[3], 0u);  // the published doubles
  std::int64_t tick;
  double t;
  std::memcpy(&tick, f.data() + 16, 8);
  std::memcpy(&t, f.data() + 24, 8);
  EXPECT_EQ(tick, 1234);
  EXPECT_EQ(t, 1.234);
  std::int64_t stamp;
  std::memcpy(&stamp, f.data() + 32, 8);
  EXPECT_EQ(stamp, 1'700'000'000'123'456'789);
  double pos[6], ori[8], vel[6], omega[6];
  float energy[2], momentum[2];
  std::int32_t ids[2];
  const char* at = f.data() + kStateHeaderBytes;
  for (auto [to, bytes] : {std::pair<void*, std::size_t>{pos, sizeof pos},
                           {ori, sizeof ori},
                           {vel, sizeof vel},
                           {omega, sizeof omega},
                           {energy, sizeof energy},
                           {momentum, sizeof momentum},
                           {ids, sizeof ids}}) {
    std::memcpy(to, at, bytes);
    at += bytes;
  }
  EXPECT_EQ(pos[4], 5);
  EXPECT_EQ(ori[5], 0.5);
  EXPECT_EQ(vel[0], -1);
  EXPECT_EQ(vel[5], -6);
  EXPECT_EQ(omega[0], 10);
  EXPECT_EQ(omega[4], 50);
  EXPECT_EQ(omega[5], 60.000000000000007);  // to the last bit
  EXPECT_EQ(energy[0], 1e-12f);
  EXPECT_EQ(energy[1], 2.5f);
  EXPECT_EQ(momentum[0], 0.25f);
  EXPECT_EQ(momentum[1], 3e-9f);
  EXPECT_EQ(ids[0], 5);
  EXPECT_EQ(ids[1], 9);

  // Arrays shorter than the ids (not from a decoder; drifts not given): zeros in their place,
  // the layout kept.
  s.angular_velocity.clear();
  const std::string g = encode_state(s, 3, {}, {1.0f});
  ASSERT_EQ(g.size(), f.size());
  std::memcpy(omega, g.data() + kStateHeaderBytes + (3 + 4 + 3) * 2 * 8, sizeof omega);
  EXPECT_EQ(omega[4], 0);
  std::memcpy(energy, g.data() + kStateHeaderBytes + 13 * 2 * 8, sizeof energy);
  std::memcpy(momentum, g.data() + kStateHeaderBytes + 13 * 2 * 8 + 8, sizeof momentum);
  EXPECT_EQ(energy[0], 0.0f);
  EXPECT_EQ(energy[1], 0.0f);
  EXPECT_EQ(momentum[0], 1.0f);
  EXPECT_EQ(momentum[1], 0.0f);
  std::memcpy(ids, g.data() + g.size() - sizeof ids, sizeof ids);
  EXPECT_EQ(ids[1], 9);
}

// Scenes of more than kExactStateMaxBodies bodies go to the page in float32: each value the
// nearest float to the published double, the same order of arrays, flagged in the header.
TEST(ViewProtocol, LargeScenesStateFrameCarriesFloat32) {
  for (const std::size_t n : {kExactStateMaxBodies, kExactStateMaxBodies + 1, std::size_t{10000}}) {
    StateFrame s;
    s.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      s.ids[i] = static_cast<std::int32_t>(7 * i + 1);
      for (int k = 0; k < 3; ++k) {
        s.position[3 * i + k] = 0.1 * static_cast<double>(i) + k + 1e-9;
        s.linear_velocity[3 * i + k] = -0.3 * static_cast<double>(k) - 1.0 / 3;
        s.angular_velocity[3 * i + k] = 1e-3 * static_cast<double>(i + k) + 2.0 / 3;
      }
      const double h = 0.001 * static_cast<double>(i);
      s.orientation[4 * i] = std::cos(h);
      s.orientation[4 * i + 3] = std::sin(h);
    }
    std::vector<float> e(n), m(n);
    for (std::size_t i = 0; i < n; ++i) {
      e[i] = static_cast<float>(i) * 1e-14f;
      m[i] = 1.0f / static_cast<float>(i + 1);
    }
    const std::string f = encode_state(s, 1, e, m);
    const bool f32 = n > kExactStateMaxBodies;
    ASSERT_EQ(state_in_float32(n), f32);
    ASSERT_EQ(f.size(), kStateHeaderBytes + n * ((f32 ? 4 : 8) * 13 + 12)) << n;
    std::uint32_t flags;
    std::memcpy(&flags, f.data() + 12, 4);
    EXPECT_EQ(flags, f32 ? kStateFloat32 : 0u);
    const std::size_t real = f32 ? 4 : 8;
    const auto value = [&](std::size_t array_at, std::size_t k) {
      const char* p = f.data() + kStateHeaderBytes + array_at * real * n + k * real;
      if (f32) {
        float x;
        std::memcpy(&x, p, 4);
        return static_cast<double>(x);
      }
      double x;
      std::memcpy(&x, p, 8);
      return x;
    };
    const auto want = [&](double x) {
      return f32 ? static_cast<double>(static_cast<float>(x)) : x;
    };
    for (std::size_t i = 0; i < n; i += n / 7 + 1) {
      for (int k = 0; k < 3; ++k) {
        EXPECT_EQ(value(0, 3 * i + k), want(s.position[3 * i + k])) << n << " " << i;
        EXPECT_EQ(value(7, 3 * i + k), want(s.linear_velocity[3 * i + k]));
        EXPECT_EQ(value(10, 3 * i + k), want(s.angular_velocity[3 * i + k]));
      }
      for (int k = 0; k < 4; ++k)
        EXPECT_EQ(value(3, 4 * i + k), want(s.orientation[4 * i + k]));
      float de, dm;
      std::int32_t id;
      const char* d = f.data() + kStateHeaderBytes + 13 * real * n;
      std::memcpy(&de, d + 4 * i, 4);
      std::memcpy(&dm, d + 4 * n + 4 * i, 4);
      std::memcpy(&id, d + 8 * n + 4 * i, 4);
      EXPECT_EQ(de, e[i]);
      EXPECT_EQ(dm, m[i]);
      EXPECT_EQ(id, s.ids[i]);
    }
  }
}

// A page names the body whose whole state it shows (pose frames, below): with a body or none, no
// id (it gets no answer), nothing else.
TEST(ViewProtocol, Watch) {
  auto r = parse_command(R"({"op":"watch","body":42})");
  ASSERT_TRUE(std::holds_alternative<PageCommand>(r));
  EXPECT_EQ(std::get<PageCommand>(r).op, Op::kWatch);
  EXPECT_EQ(std::get<PageCommand>(r).body, 42);
  r = parse_command(R"({"op":"watch"})");
  ASSERT_TRUE(std::holds_alternative<PageCommand>(r));
  EXPECT_EQ(std::get<PageCommand>(r).body, -1);
  EXPECT_EQ(refusal(R"({"op":"watch","body":-1})"), "body: expected a body id >= 0");
  EXPECT_EQ(refusal(R"({"op":"watch","body":"ball"})"), "body: expected a body id >= 0");
  EXPECT_EQ(refusal(R"({"op":"watch","body":1,"force":[1,0,0]})"), "watch: unexpected field");
  EXPECT_EQ(refusal(R"({"op":"watch","body":1,"steps":3})"), "watch: unexpected field");
  // Allowed in both modes (playback's frames are whole: there it changes nothing).
  for (const bool playback : {false, true})
    EXPECT_EQ(refusal_in_mode(std::get<PageCommand>(parse_command(R"({"op":"watch","body":1})")),
                              playback),
              "");
}

// Live scenes of more than kExactStateMaxBodies bodies: float32 poses and ids (32 B a body), the
// worst drifts with their slots, then the watched bodies' published doubles to the last bit, in
// the order asked, skipping ids the state does not hold.
TEST(ViewProtocol, PoseFrameLayout) {
  const std::size_t n = 300;
  StateFrame s;
  s.resize(n);
  s.tick = 77;
  s.sim_time = 0.077;
  s.stamp_ns = 123456789;
  for (std::size_t i = 0; i < n; ++i) {
    const double x = static_cast<double>(i);
    s.ids[i] = static_cast<std::int32_t>(1000 + i);
    for (std::size_t k = 0; k < 3; ++k) {
      s.position[3 * i + k] = x / 3 + static_cast<double>(k);
      s.linear_velocity[3 * i + k] = -x / 7 - static_cast<double>(k);
      s.angular_velocity[3 * i + k] = x / 11 + 1e-13;
    }
    s.orientation[4 * i] = std::cos(x / 100);
    s.orientation[4 * i + 2] = std::sin(x / 100);
  }
  std::vector<float> e(n, 0.0f), m(n, 0.0f);
  e[17] = 3e-12f;
  e[250] = 2.5e-9f;  // the worst energy drift
  m[3] = 1e-3f;      // the worst momentum drift
  m[4] = std::nanf("");
  const std::vector<std::int32_t> watched = {1250, 5, 1003};  // 5: not in the state
  const std::string f = encode_pose_state(s, 9, e, m, watched);
  ASSERT_EQ(f.size(), pose_state_bytes(n, 2));
  ASSERT_EQ(f.size(), kStateHeaderBytes + 32 * n + 24 + 2 * kWatchedRecordBytes);
  std::uint32_t head[4];
  std::memcpy(head, f.data(), 16);
  EXPECT_EQ(head[0], kStateMagic);
  EXPECT_EQ(head[1], n);
  EXPECT_EQ(head[2], 9u);
  EXPECT_EQ(head[3], kStatePoses);
  std::int64_t tick;
  std::memcpy(&tick, f.data() + 16, 8);
  EXPECT_EQ(tick, 77);
  const auto f32 = [&](std::size_t at) {
    float x;
    std::memcpy(&x, f.data() + at, 4);
    return x;
  };
  const auto i32 = [&](std::size_t at) {
    std::int32_t x;
    std::memcpy(&x, f.data() + at, 4);
    return x;
  };
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t k = 0; k < 3; ++k)
      ASSERT_EQ(f32(kStateHeaderBytes + 4 * (3 * i + k)),
                static_cast<float>(s.position[3 * i + k]));
    for (std::size_t k = 0; k < 4; ++k) {
      ASSERT_EQ(f32(kStateHeaderBytes + 12 * n + 4 * (4 * i + k)),
                static_cast<float>(s.orientation[4 * i + k]));
    }
    ASSERT_EQ(i32(kStateHeaderBytes + 28 * n + 4 * i), s.ids[i]);
  }
  const std::size_t worst = kStateHeaderBytes + 32 * n;
  EXPECT_EQ(f32(worst), 2.5e-9f);
  EXPECT_EQ(i32(worst + 4), 250);
  EXPECT_EQ(f32(worst + 8), 1e-3f);  // NaN is never the worst
  EXPECT_EQ(i32(worst + 12), 3);
  EXPECT_EQ(i32(worst + 16), 2);  // records
  const std::size_t records = worst + 24;
  ASSERT_EQ(records % 8, 0u);  // the page reads the doubles as a Float64Array
  for (const auto& [r, slot] : {std::pair{0, std::size_t{250}}, std::pair{1, std::size_t{3}}}) {
    const std::size_t at = records + static_cast<std::size_t>(r) * kWatchedRecordBytes;
    EXPECT_EQ(i32(at), static_cast<std::int32_t>(slot));
    EXPECT_EQ(f32(at + 4), e[slot]);
    if (slot == 3) {
      EXPECT_EQ(f32(at + 8), 1e-3f);
    }
    double x[13];
    std::memcpy(x, f.data() + at + 16, sizeof x);
    for (std::size_t k = 0; k < 3; ++k) {
      EXPECT_EQ(x[k], s.position[3 * slot + k]);
      EXPECT_EQ(x[7 + k], s.linear_velocity[3 * slot + k]);
      EXPECT_EQ(x[10 + k], s.angular_velocity[3 * slot + k]);  // to the last bit
    }
    for (std::size_t k = 0; k < 4; ++k)
      EXPECT_EQ(x[3 + k], s.orientation[4 * slot + k]);
  }
  // Every drift 0: no worst body; no watch: no records; beyond kMaxWatched: the first ones.
  const std::string g = encode_pose_state(s, 9, {}, {}, {});
  ASSERT_EQ(g.size(), pose_state_bytes(n, 0));
  std::int32_t none;
  std::memcpy(&none, g.data() + worst + 4, 4);
  EXPECT_EQ(none, -1);
  std::vector<std::int32_t> many;
  for (std::int32_t id = 1000; id < 1100; ++id)
    many.push_back(id);
  EXPECT_EQ(encode_pose_state(s, 9, e, m, many).size(), pose_state_bytes(n, kMaxWatched));
}

TEST(ViewProtocol, StatsForTheHud) {
  StatsReport s;
  s.tick = 7;
  s.lateness_p99_us = 12.5;
  s.bodies_frozen = 3;
  s.rejected.over_limit = 2;
  s.rejected.rate_limited = 1;
  const std::string j = stats_json(s);
  EXPECT_NE(j.find(R"("lateness_p99_us":12.5,)"), std::string::npos) << j;
  EXPECT_NE(j.find(R"("refused":3,)"), std::string::npos) << j;
  EXPECT_NE(j.find(R"("frozen":3})"), std::string::npos) << j;
}

TEST(ViewProtocol, WrenchesForThePage) {
  std::vector<AcceptedCommand> accepted;
  AcceptedCommand control;
  control.kind = AcceptedKind::kControl;
  accepted.push_back(control);
  AcceptedCommand w;
  w.kind = AcceptedKind::kWrench;
  w.tick = 42;
  w.body_id = 3;
  w.force = {1, -2, 0.5};
  w.point = {0, 0, 0.25};
  w.force_frame = Frame::kBody;
  w.ttl = 0.1;
  w.key = 7;
  accepted.push_back(w);
  const std::string j = wrenches_json(accepted);
  EXPECT_EQ(j, R"({"type":"wrenches","wrenches":[{"body":3,"tick":42,"ttl":0.10000000000000001,)"
               R"("force":[1,-2,0.5],"force_frame":"body","point":[0,0,0.25],"torque":[0,0,0],)"
               R"("torque_frame":"world","key":7}]})");
  EXPECT_EQ(wrenches_json({}), R"({"type":"wrenches","wrenches":[]})");
  // A pure torque in B, with the tick it stops at (playback: cut short by a newer wrench or a
  // reset); `until` goes with the wrench of the same index, the control before it is skipped.
  AcceptedCommand torque = w;
  torque.force = {0, 0, 0};
  torque.torque = {0.5, 0, -2};
  torque.torque_frame = Frame::kBody;
  EXPECT_EQ(wrenches_json({control, torque}, {0, 50}),
            R"({"type":"wrenches","wrenches":[{"body":3,"tick":42,"ttl":0.10000000000000001,)"
            R"("force":[0,0,0],"force_frame":"body","point":[0,0,0.25],"torque":[0.5,0,-2],)"
            R"("torque_frame":"body","key":7,"until":50}]})");
  // A flood: only the last kMaxWrenchesShown, so a message stays small.
  accepted.clear();
  for (int i = 0; i < 1000; ++i) {
    w.body_id = i;
    accepted.push_back(w);
  }
  const std::string many = wrenches_json(accepted);
  std::size_t count = 0;
  for (std::size_t p = many.find("\"body\":"); p != std::string::npos;
       p = many.find("\"body\":", p + 1))
    ++count;
  EXPECT_EQ(count, kMaxWrenchesShown);
  EXPECT_EQ(many.find(R"("body":935,)"), std::string::npos);
  EXPECT_NE(many.find(R"("body":936,)"), std::string::npos);
  EXPECT_NE(many.find(R"("body":999,)"), std::string::npos);
  EXPECT_LT(many.size(), 300 * kMaxWrenchesShown);
}

TEST(ViewProtocol, SceneAndBoxOfMoments) {
  const double inertia[6] = {0.1, 0.2, 0.25, 0, 0, 0};
  const MomentBox box = box_of_moments(3, inertia);
  // A uniform box of mass 3 with these moments: a^2 = 6 (Iyy + Izz - Ixx) / m.
  const double a = std::sqrt(6 * (0.2 + 0.25 - 0.1) / 3), c = std::sqrt(6 * (0.1 + 0.2 - 0.25) / 3);
  EXPECT_NEAR(box.size[0], a, 1e-12);
  EXPECT_NEAR(box.size[2], c, 1e-12);
  SceneDescription d;
  d.scene_name = "a \"quoted\" scene";
  d.ids = {0};
  d.names = {"b"};
  d.masses = {1};
  d.inertia = {1, 1, 1, 0, 0, 0};
  d.shape_kinds = {ShapeKind::kCapsule};
  d.shape_dims = {0.1, 0.3, 0};
  d.gravity = {0, 0, -9.81};
  const std::string j = scene_json(d, 2);
  EXPECT_NE(j.find(R"("name":"a \"quoted\" scene")"), std::string::npos) << j;
  EXPECT_NE(j.find(R"("gravity":[0,0,-9.8100000000000005])"), std::string::npos) << j;
  EXPECT_NE(j.find(R"("max_force":0,"max_torque":0,)"), std::string::npos) << j;
  EXPECT_NE(j.find(R"("mass":1,"inertia":[1,1,1,0,0,0])"), std::string::npos) << j;
  EXPECT_NE(j.find(R"("shape":"capsule","dims":[0.10000000000000001,0.29999999999999999,0])"),
            std::string::npos)
      << j;
  EXPECT_EQ(j.find("parts"), std::string::npos) << j;  // none: the message is as it was
  // Static parts: a plane as its frame and a box as its pose and size.
  d.part_names = {"ground", "ramp"};
  d.part_kinds = {ShapeKind::kPlane, ShapeKind::kBox};
  d.part_position = {0, 0, -0.5, 2, 0, 0.25};
  d.part_orientation = {1, 0, 0, 0, 0.5, 0, 0.5, 0};
  d.part_dims = {0, 0, 0, 1, 2, 0.5};
  d.part_restitution = {0, 0};
  d.part_friction = {0.5, 0.5};
  ASSERT_TRUE(d.lengths_agree());
  const std::string k = scene_json(d, 3);
  EXPECT_NE(k.find(R"(,"parts":[{"name":"ground","shape":"plane","p":[0,0,-0.5],"q":[1,0,0,0],)"
                   R"("dims":[0,0,0]},{"name":"ramp","shape":"box","p":[2,0,0.25],)"
                   R"("q":[0.5,0,0.5,0],"dims":[1,2,0.5]}]})"),
            std::string::npos)
      << k;
}

TEST(ViewOptions, Listen) {
  const std::string_view ok[] = {"--listen", "0.0.0.0:9000", "--read-only"};
  const ViewOptions o = parse_options(ok);
  EXPECT_EQ(o.host, "0.0.0.0");
  EXPECT_EQ(o.port, 9000);
  EXPECT_TRUE(o.read_only);
  // Host names (resolved when rigid-view binds) and IPv6 addresses in brackets.
  for (const auto& [arg, host] : std::vector<std::pair<std::string_view, std::string>>{
           {"localhost:8765", "localhost"},
           {"view-host.example.org:0", "view-host.example.org"},
           {"[::1]:8765", "::1"}}) {
    const std::string_view args[] = {"--listen", arg};
    EXPECT_EQ(parse_options(args).host, host) << arg;
  }
  EXPECT_EQ(url_host("::1"), "[::1]");
  EXPECT_EQ(url_host("localhost"), "localhost");
  for (const std::string_view bad :
       {"1.2.3.4:70000", "1.2.3.4:", ":80", "1.2.3.4", "-host:80", "host-:80", "a..b:80", "a b:80",
        "[::1:80", "[]:80", "[zz::1]:80", "::1:80"}) {
    const std::string_view args[] = {"--listen", bad};
    EXPECT_THROW(parse_options(args), clients::UsageError) << bad;
  }
  const std::string_view unknown[] = {"--frobnicate", "1"};
  EXPECT_THROW(parse_options(unknown), clients::UsageError);
}

}  // namespace
}  // namespace rigid::view
