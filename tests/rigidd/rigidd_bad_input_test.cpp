// Bad input to a real rigidd over loopback, beyond what rigidd_bus_test's
// BadInputIsRejectedCountedAndNeverReachesTheWorld covers (a NaN force, an unknown id and name, a
// force over the limit, a force frame of 7, a step of 0, a stale sequence number, six garbage
// bytes on LCM): non-finite values in every other field, absurd magnitudes (finite components
// whose norm overflows, huge lever arms, times to live), every out-of-range enumeration and
// argument, unknown bodies with hostile names, and on LCM truncated, oversized, forged and
// mistyped payloads. Each test asserts that Stats counts every command by its reason, that the
// first refusal is logged (bounded, printable) and refused controls answered with their reason,
// and that the world never saw any of it. Every wait is bounded; rigidd is stopped by PID with
// SIGTERM (exit status 0) and killed with its process group if a test fails first. Needs
// scripts/net-setup (LCM's multicast route on lo) and CYCLONEDDS_URI (ctest sets it).
#include <gtest/gtest.h>

#include <chrono>
#include <climits>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "bus_client.hpp"
#include "raw_lcm_sender.hpp"
#include "rigidd_process.hpp"
#include "transport/lcm/lcm_codec.hpp"
#include "transport/topic.hpp"

namespace rigid::rigidd::testing {
namespace {

using namespace std::chrono_literals;
using rigid::Bus;
using rigid::ControlCommand;
using rigid::ControlKind;
using rigid::Outcome;
using rigid::RejectCounts;
using rigid::WrenchCommand;

const std::string kProbe = std::string(RIGIDD_TEST_SCENES) + "/probe.pbtxt";
constexpr int kPuck = 1;  // the probe scene's point mass of 2 kg at x = 1; the brick is body 0
constexpr double kInf = std::numeric_limits<double>::infinity();
const double kNaN = std::nan("");

ControlCommand control(ControlKind kind, std::int64_t steps = 0, double rtf = 0.0) {
  ControlCommand c;
  c.command = kind;
  c.steps = steps;
  c.rtf = rtf;
  return c;
}

// A wrench rigidd would accept: 1 N on the puck for one tick.
WrenchCommand good_wrench() {
  WrenchCommand w;
  w.body_id = kPuck;
  w.force = {1, 0, 0};
  return w;
}

class BadInput : public ::testing::TestWithParam<Bus> {
 protected:
  void SetUp() override { start(GetParam()); }
  void start(Bus bus) {
    bus_ = bus;
    prefix_ = unique_prefix("bad");
    daemon_.emplace(std::vector<std::string>{
        "--scene", kProbe, "--transport", bus == Bus::kDds ? "dds" : "lcm", "--prefix", prefix_});
    try {
      client_.emplace(bus, prefix_);
    } catch (const transport::TransportError& e) {
      FAIL() << e.what() << " (run scripts/net-setup as root; CYCLONEDDS_URI comes from ctest)";
    }
    // Until rigidd answers a harmless request: from then on our commands reach it.
    ASSERT_TRUE(client_->handshake(control(ControlKind::kSetRtf, 0, 1.0), 10s))
        << "no answer from rigidd within 10 s; its stderr:\n"
        << daemon_->stderr_text();
  }
  void TearDown() override {
    client_.reset();
    daemon_.reset();  // kills the process group if still running
  }
  void stop() { EXPECT_EQ(daemon_->terminate(1000ms), 0) << daemon_->stderr_text(); }

  // Until Stats shows exactly these refusals (and only these).
  void expect_rejected(const RejectCounts& expected) {
    const bool seen = client_->wait(
        [&] { return client_->stats_locked() && client_->stats_locked()->rejected == expected; },
        10s);
    const auto s = client_->last_stats();
    ASSERT_TRUE(seen) << "Stats never showed the expected refusals; last: "
                      << (s ? describe(s->rejected) : std::string("no Stats"));
  }
  static std::string describe(const RejectCounts& r) {
    return "non_finite " + std::to_string(r.non_finite) + ", unknown_body " +
           std::to_string(r.unknown_body) + ", over_limit " + std::to_string(r.over_limit) +
           ", undecodable " + std::to_string(r.undecodable) + ", stale_sequence " +
           std::to_string(r.stale_sequence) + ", queue_full " + std::to_string(r.queue_full) +
           ", invalid " + std::to_string(r.invalid);
  }

  // rigidd's log line for the first refusal of `reason` (housekeeping writes it within ~100 ms of
  // the refusal), without its "rigidd: " prefix; empty if none within 10 s (a loaded sanitizer
  // build is slow; the deadline only bounds a failing run).
  std::string refusal_line(const std::string& reason) {
    const std::string key = "rigidd: rejected " + reason + ": ";
    const auto deadline = std::chrono::steady_clock::now() + 10s;
    for (;;) {
      const std::string err = daemon_->stderr_text();
      const auto at = err.find(key);
      if (at != std::string::npos) {
        EXPECT_EQ(err.find(key, at + 1), std::string::npos) << key << " logged twice:\n" << err;
        return err.substr(at + 8, err.find('\n', at) - at - 8);
      }
      if (std::chrono::steady_clock::now() > deadline) return {};
      std::this_thread::sleep_for(20ms);
    }
  }
  std::string who(std::int64_t seq) const {
    return "wrench from source " + std::to_string(client_->source()) + " seq " +
           std::to_string(seq) + ": ";
  }

  // A state published after everything sent so far was taken in, with the puck's x velocity as
  // given and everything else as the probe scene starts: brick and puck at rest, the puck at x = 1.
  void expect_world(double puck_vx) {
    // Refusals are counted before anything reaches the loop; a fresh state after that shows
    // whatever did reach it.
    const std::int64_t after = client_->last_state()->state.tick;
    ASSERT_TRUE(client_->wait(
        [&] { return client_->states_locked().back().state.tick > after + 20; }, 10s));
    const rigid::StateFrame s = client_->last_state()->state;
    for (std::size_t i = 0; i < 6; ++i) {
      EXPECT_EQ(s.angular_velocity[i], 0.0) << "at tick " << s.tick;
      if (i != 3 * kPuck) {
        EXPECT_EQ(s.linear_velocity[i], 0.0) << "at tick " << s.tick;
      }
    }
    EXPECT_EQ(s.linear_velocity[3 * kPuck], puck_vx) << "at tick " << s.tick;
    EXPECT_EQ(s.position[0], 0.0);
    EXPECT_EQ(s.position[1], 0.0);
    EXPECT_EQ(s.position[2], 0.0);
    if (puck_vx == 0.0) {
      EXPECT_EQ(s.position[3 * kPuck], 1.0);
    }
  }

  Bus bus_ = Bus::kDds;
  std::string prefix_;
  std::optional<RigiddProcess> daemon_;
  std::optional<BusClient> client_;
};

std::string bus_name(const ::testing::TestParamInfo<Bus>& info) {
  return info.param == Bus::kDds ? "Dds" : "Lcm";
}

TEST_P(BadInput, NonFiniteNumbersInAnyFieldAreRefused) {
  WrenchCommand w = good_wrench();
  w.force = {kInf, 0, 0};
  const std::int64_t first = client_->send(w);
  w = good_wrench();
  w.force = {0, -kInf, 0};
  client_->send(w);
  w = good_wrench();
  w.point = {kNaN, 0, 0};
  client_->send(w);
  w = good_wrench();
  w.torque = {0, 0, kNaN};
  client_->send(w);
  w = good_wrench();
  w.ttl = kNaN;
  client_->send(w);
  w = good_wrench();
  w.ttl = kInf;
  client_->send(w);
  // Wrenches and controls travel on different topics, which DDS does not order between: the
  // control goes only once the wrenches are counted, so the first refusal logged is the first
  // wrench's (CI once saw the control's logged first).
  RejectCounts wrenches;
  wrenches.non_finite = 6;
  expect_rejected(wrenches);
  const auto rtf = client_->request(control(ControlKind::kSetRtf, 0, kNaN), 5s);
  ASSERT_TRUE(rtf) << "a refused control is answered";
  EXPECT_EQ(rtf->outcome, Outcome::kInvalid);
  EXPECT_EQ(rtf->message, "rtf is not a finite number");

  RejectCounts expected;
  expected.non_finite = 7;
  expect_rejected(expected);
  EXPECT_EQ(refusal_line("non_finite"),
            "rejected non_finite: " + who(first) +
                "force (inf, 0, 0) (the first of its kind; Stats counts the others)");
  expect_world(0.0);
  stop();
}

TEST_P(BadInput, AbsurdMagnitudesAreRefusedAsOverLimit) {
  // The probe's limits: max_force 100 N, max_torque 50 N m, max_ttl 5 s.
  WrenchCommand w = good_wrench();
  w.force = {1e308, 1e308, 0};  // finite components, an infinite norm
  const std::int64_t first = client_->send(w);
  w = good_wrench();
  w.torque = {0, 1e300, 0};
  client_->send(w);
  w = good_wrench();
  w.point = {1e6, 0, 0};  // 1 N at a million metres: 1e6 N m
  w.force = {0, 1, 0};
  client_->send(w);
  w = good_wrench();
  w.ttl = 1e9;
  client_->send(w);
  w = good_wrench();
  w.ttl = 5.000001;
  client_->send(w);
  // The limits themselves are allowed: 100 N for one tick, 0.05 m/s on the 2 kg puck.
  w = good_wrench();
  w.force = {60, 80, 0};  // |f| = 100
  w.point = {0.5, 0, 0};  // |p x f| = 40 N m
  w.torque = {0, 0, 0};
  client_->send(w);

  RejectCounts expected;
  expected.over_limit = 5;
  expect_rejected(expected);
  EXPECT_EQ(refusal_line("over_limit"),
            "rejected over_limit: " + who(first) +
                "|force| inf N > max_force 100 (the first of its kind; Stats counts the others)");
  // The point mass does not turn; the accepted push moved it along (60, 80, 0) / 2 kg * 1 ms.
  const std::int64_t after = client_->last_state()->state.tick;
  ASSERT_TRUE(
      client_->wait([&] { return client_->states_locked().back().state.tick > after + 20; }, 10s));
  const rigid::StateFrame s = client_->last_state()->state;
  EXPECT_NEAR(s.linear_velocity[3 * kPuck], 0.03, 1e-15);
  EXPECT_NEAR(s.linear_velocity[3 * kPuck + 1], 0.04, 1e-15);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(s.linear_velocity[i], 0.0);   // the brick
    EXPECT_EQ(s.angular_velocity[i], 0.0);  // the brick
  }
  stop();
}

TEST_P(BadInput, OutOfRangeEnumerationsAndArgumentsAreRefusedAsInvalid) {
  WrenchCommand w = good_wrench();
  w.ttl = -1e-9;
  const std::int64_t first = client_->send(w);
  w = good_wrench();
  w.force_frame = static_cast<rigid::Frame>(-1);
  client_->send(w);
  w = good_wrench();
  w.torque = {0, 0, 1};
  w.torque_frame = static_cast<rigid::Frame>(2);
  client_->send(w);
  w = good_wrench();
  w.torque_frame = static_cast<rigid::Frame>(INT32_MIN);
  client_->send(w);
  // The wrenches refused before any control is sent: on DDS they travel on another topic, so a
  // control sent now could be taken first and be the one logged.
  RejectCounts wrenches;
  wrenches.invalid = 4;
  expect_rejected(wrenches);
  // Each refused control is answered with its reason.
  const struct {
    ControlCommand c;
    const char* message;
  } controls[] = {
      {control(static_cast<ControlKind>(99)), "unknown command"},
      {control(ControlKind::kNone), "unknown command"},
      {control(static_cast<ControlKind>(-3)), "unknown command"},
      {control(ControlKind::kStep, -5), "steps must be >= 1 and <= 1000000000"},
      {control(ControlKind::kStep, std::int64_t{1} << 62), "steps must be >= 1 and <= 1000000000"},
      {control(ControlKind::kSetRtf, 0, 0.0), "rtf must be > 0 and <= 1000"},
      {control(ControlKind::kSetRtf, 0, -1.0), "rtf must be > 0 and <= 1000"},
      {control(ControlKind::kSetRtf, 0, 1e6), "rtf must be > 0 and <= 1000"},
  };
  for (const auto& k : controls) {
    const auto reply = client_->request(k.c, 5s);
    ASSERT_TRUE(reply) << "no answer to " << k.message;
    EXPECT_EQ(reply->outcome, Outcome::kInvalid);
    EXPECT_EQ(reply->message, k.message);
  }

  RejectCounts expected;
  expected.invalid = 4 + 8;
  expect_rejected(expected);
  EXPECT_EQ(refusal_line("invalid"),
            "rejected invalid: " + who(first) +
                "ttl -1e-09 < 0 (the first of its kind; Stats counts the others)");
  expect_world(0.0);
  stop();
}

TEST_P(BadInput, UnknownBodiesAreRefusedAndHostileNamesLoggedBoundedAndPrintable) {
  // 128 bytes (the longest name the buses carry: msgs/rigid.idl) of control characters, bytes
  // above 0x7f and quotes: the log shows a printable excerpt of the first 64. Longer names never
  // reach rigidd (tests/security: the reader's deserializer drops them).
  std::string hostile;
  for (int i = 0; i < 128; ++i)
    hostile.push_back(static_cast<char>(i % 3 == 0 ? '\n' : (i % 3 == 1 ? '\xe9' : '\'')));
  WrenchCommand w = good_wrench();
  w.body_id = -1;
  w.body_name = hostile;
  const std::int64_t first = client_->send(w);
  w = good_wrench();
  w.body_id = 2;  // the scene has bodies 0 and 1
  client_->send(w);
  w = good_wrench();
  w.body_id = INT32_MAX;
  client_->send(w);
  w = good_wrench();
  w.body_id = -1;  // by name, and the name is empty
  client_->send(w);
  w = good_wrench();
  w.body_id = -1;
  w.body_name = "Puck";  // names are case-sensitive
  client_->send(w);

  RejectCounts expected;
  expected.unknown_body = 5;
  expect_rejected(expected);
  std::string shown;
  for (int i = 0; i < 64; ++i)
    shown += i % 3 == 2 ? '\'' : '?';
  const std::string line = refusal_line("unknown_body");
  EXPECT_EQ(line, "rejected unknown_body: " + who(first) + "body_name '" + shown +
                      "' (the first of its kind; Stats counts the others)");
  expect_world(0.0);
  stop();
}

INSTANTIATE_TEST_SUITE_P(Bus, BadInput, ::testing::Values(Bus::kDds, Bus::kLcm), bus_name);

// Payloads only LCM can deliver (a DDS sample that does not deserialize never reaches the reader):
// raw datagrams on rigidd's wrench and control channels. Each is made from a wrench rigidd would
// accept (50 N on the puck, which would show at once), so a lenient decoder would move the world.
class BadLcmPayload : public BadInput {
 protected:
  void SetUp() override { start(Bus::kLcm); }
  std::string channel(transport::Topic topic) const {
    return transport::lcm_channel_names(prefix_)[transport::index_of(topic)];
  }
  void send(transport::Topic topic, const std::vector<std::uint8_t>& payload) {
    ASSERT_TRUE(send_raw_lcm(channel(topic), payload));
    // UDP: a burst of datagrams can overflow the receiver's socket buffer when rigidd runs slowly
    // (under a sanitizer, beside other tests), and a lost one is not a refusal to count. Spaced
    // out, each reaches rigidd.
    std::this_thread::sleep_for(10ms);
  }
};

TEST_F(BadLcmPayload, TruncatedOversizedForgedAndMistypedPayloadsAreCountedAsUndecodable) {
  transport::lcm::Codec codec;
  WrenchCommand push = good_wrench();
  push.source = client_->source();
  push.seq = client_->next_seq();
  push.force = {50, 0, 0};
  push.body_id = -1;
  push.body_name = "puck";
  const auto encoded = codec.encode(push);
  const std::vector<std::uint8_t> valid(encoded.begin(), encoded.end());
  // The body name's length field: after the fingerprint (8), source and seq (16), key and body_id
  // (8).
  constexpr std::size_t kNameLength = 8 + 16 + 8;
  ASSERT_EQ(valid[kNameLength + 3], 5) << "the layout this test forges has changed";

  using transport::Topic;
  std::vector<std::uint8_t> p(valid.begin(), valid.end() - 1);  // one byte short
  send(Topic::kWrench, p);
  send(Topic::kWrench, {valid.begin(), valid.begin() + 8});  // the fingerprint alone
  send(Topic::kWrench, {});                                  // nothing
  p = valid;
  p.push_back(0);  // one byte too many
  send(Topic::kWrench, p);
  p.assign(60000, 0x5a);  // a large datagram of garbage
  send(Topic::kWrench, p);
  p = valid;
  p[kNameLength] = 0x7f;  // the name's length forged to ~2^31
  send(Topic::kWrench, p);
  p = valid;
  p[kNameLength] = 0x80;  // and to a negative length
  send(Topic::kWrench, p);
  p = valid;
  p[3] ^= 0x01;  // another type's fingerprint
  send(Topic::kWrench, p);
  send(Topic::kControl, valid);  // a wrench where a control is expected

  RejectCounts expected;
  expected.undecodable = 9;
  expect_rejected(expected);
  EXPECT_EQ(client_->last_stats()->lcm.decode_failures, 9);
  EXPECT_EQ(refusal_line("undecodable"),
            "rejected undecodable: lcm payload on wrench (" + std::to_string(valid.size() - 1) +
                " bytes): truncated payload (the first of its kind; Stats counts the others)");
  expect_world(0.0);

  // The same bytes, intact, are accepted: the forgeries above were one byte from a push.
  send(Topic::kWrench, valid);
  const std::int64_t after = client_->last_state()->state.tick;
  ASSERT_TRUE(client_->wait(
      [&] {
        const auto& s = client_->states_locked().back().state;
        return s.tick > after && s.linear_velocity[3 * kPuck] > 0;
      },
      3s));
  // 50 N on 2 kg for one tick of 1 ms.
  EXPECT_NEAR(client_->last_state()->state.linear_velocity[3 * kPuck], 0.025, 1e-15);
  stop();
}

}  // namespace
}  // namespace rigid::rigidd::testing
