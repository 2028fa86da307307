// rigidd's switches seen from the bus, each against a rigidd without it (the control that shows
// the test can tell): --reliable-state offers the state reliably (a reliable reader, written
// against msgs/rigid.idl with Cyclone's C API alone, matches it, and does not match a default
// rigidd: incompatible reliability), and --controls off refuses every control and edit with its
// reason and counts it while wrenches still act. Every wait is bounded by a positive event (a
// state, an incompatible-QoS report, a reply). Needs scripts/net-setup and CYCLONEDDS_URI (ctest
// sets it).
#include <dds/dds.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "bus_client.hpp"
#include "rigid.h"  // idlc's C types of msgs/rigid.idl
#include "rigidd_process.hpp"

namespace rigid::rigidd::testing {
namespace {

using namespace std::chrono_literals;
using rigid::Bus;
using rigid::ControlKind;
using rigid::Outcome;

const std::string kProbe = std::string(RIGIDD_TEST_SCENES) + "/probe.pbtxt";

// What a reliable reader of PREFIX/rigid/state got from rigidd within `patience`: states, or
// Cyclone's report that the writer it found offers less than it asked for.
struct ReliableReading {
  int states = 0;
  std::uint32_t incompatible = 0;  // requested-incompatible-QoS reports
  std::uint32_t policy = DDS_INVALID_QOS_POLICY_ID;
};

ReliableReading read_reliably(const std::string& prefix, std::chrono::milliseconds patience) {
  ReliableReading out;
  const dds_entity_t participant = dds_create_participant(DDS_DOMAIN_DEFAULT, nullptr, nullptr);
  if (participant < 0) return out;
  dds_qos_t* qos = dds_create_qos();
  dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_MSECS(10));
  dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, 16);
  const dds_entity_t topic = dds_create_topic(participant, &rigid_WorldState_desc,
                                              (prefix + "/rigid/state").c_str(), qos, nullptr);
  const dds_entity_t reader = dds_create_reader(participant, topic, qos, nullptr);
  dds_delete_qos(qos);
  const auto end = std::chrono::steady_clock::now() + patience;
  while (reader > 0 && std::chrono::steady_clock::now() < end && out.states < 5 &&
         out.incompatible == 0) {
    void* samples[8] = {};
    dds_sample_info_t infos[8];
    const dds_return_t got = dds_take(reader, samples, infos, 8, 8);
    if (got > 0) {
      for (dds_return_t i = 0; i < got; ++i)
        out.states += infos[i].valid_data ? 1 : 0;
      dds_return_loan(reader, samples, got);
    }
    dds_requested_incompatible_qos_status_t status{};
    if (dds_get_requested_incompatible_qos_status(reader, &status) == DDS_RETCODE_OK) {
      out.incompatible = status.total_count;
      out.policy = status.last_policy_id;
    }
    std::this_thread::sleep_for(10ms);
  }
  dds_delete(participant);
  return out;
}

TEST(RigiddFlags, ReliableStateOffersTheStateReliably) {
  for (const bool reliable : {false, true}) {
    SCOPED_TRACE(reliable ? "--reliable-state" : "default");
    const std::string prefix = unique_prefix("reliable");
    std::vector<std::string> args{"--scene", kProbe, "--transport", "dds", "--prefix", prefix};
    if (reliable) args.push_back("--reliable-state");
    RigiddProcess daemon(args);
    const ReliableReading r = read_reliably(prefix, 10s);
    if (reliable) {
      EXPECT_GE(r.states, 5) << daemon.stderr_text();
      EXPECT_EQ(r.incompatible, 0u);
    } else {
      // Best effort, as documented: a reliable reader finds the writer and cannot match it.
      EXPECT_EQ(r.states, 0);
      EXPECT_GE(r.incompatible, 1u) << daemon.stderr_text();
      EXPECT_EQ(r.policy, DDS_RELIABILITY_QOS_POLICY_ID);
    }
    EXPECT_EQ(daemon.terminate(2000ms), 0) << daemon.stderr_text();
  }
}

class ControlsFlag : public ::testing::TestWithParam<Bus> {};

TEST_P(ControlsFlag, ControlsOffRefusesEveryControlWhileWrenchesAct) {
  for (const bool off : {false, true}) {
    SCOPED_TRACE(off ? "--controls off" : "default");
    const std::string prefix = unique_prefix("controls");
    std::vector<std::string> args{"--scene",     kProbe,
                                  "--transport", GetParam() == Bus::kDds ? "dds" : "lcm",
                                  "--prefix",    prefix};
    if (off) {
      args.push_back("--controls");
      args.push_back("off");
    }
    RigiddProcess daemon(args);
    BusClient client(GetParam(), prefix);
    rigid::ControlCommand pause;
    pause.command = ControlKind::kPause;
    // Any answer says rigidd hears us: a refusal is one.
    const auto first = client.handshake(pause, 10s);
    ASSERT_TRUE(first) << daemon.stderr_text();
    if (off) {
      EXPECT_EQ(first->outcome, Outcome::kNotAllowed) << first->message;
      EXPECT_NE(first->message.find("--controls off"), std::string::npos) << first->message;
    } else {
      EXPECT_EQ(first->outcome, Outcome::kOk) << first->message;
    }
    // An edit is allowed where controls are: refused alike, with the reason (asked first, while
    // this sender's refusals are still answered).
    rigid::EditCommand edit;
    edit.kind = rigid::EditKind::kSetState;
    edit.body_id = 0;
    edit.set = rigid::kSetPosition;
    edit.position = {0, 0, 5};
    const auto edited = client.request(edit, 5s);
    ASSERT_TRUE(edited) << daemon.stderr_text();
    EXPECT_EQ(edited->command, rigid::kReplyToEdit);
    if (off) {
      EXPECT_EQ(edited->outcome, Outcome::kNotAllowed) << edited->message;
      EXPECT_NE(edited->message.find("--controls off"), std::string::npos) << edited->message;
    } else {
      EXPECT_EQ(edited->outcome, Outcome::kOk) << edited->message;
    }
    // Every other control, at once (rigidd answers at most 5 refusals a second per sender: the
    // count in Stats is what says each was refused).
    for (const ControlKind kind :
         {ControlKind::kStep, ControlKind::kResume, ControlKind::kReset, ControlKind::kSetRtf}) {
      rigid::ControlCommand c;
      c.command = kind;
      c.steps = 3;
      c.rtf = 2.0;
      client.send(c);
    }
    const std::int64_t controls_sent = client.next_seq() - 1;  // the handshake's pauses included
    // A wrench acts either way: the puck (2 kg) under 2 N for 0.1 s.
    rigid::WrenchCommand w;
    w.body_id = 1;
    w.force = {2, 0, 0};
    w.ttl = 0.1;
    client.send(w);
    ASSERT_TRUE(client.wait(
        [&] {
          return !client.states_locked().empty() &&
                 client.states_locked().back().state.linear_velocity[3] > 0.09;
        },
        5s))
        << daemon.stderr_text();
    const std::int64_t tick = client.last_state()->state.tick;
    ASSERT_TRUE(client.wait(
        [&] { return client.stats_locked() && client.stats_locked()->tick > tick; }, 5s));
    const rigid::StatsReport stats = *client.last_stats();
    if (off) {
      // Each control that reached rigidd refused and counted (a pause of the handshake sent
      // before DDS discovery matched reached no one); none took effect: the loop never paused
      // (its ticks ran on) nor reset (its ticks never went back).
      EXPECT_GE(stats.rejected.not_permitted, 5);
      EXPECT_LE(stats.rejected.not_permitted, controls_sent);
      EXPECT_EQ(stats.commands_accepted, 1) << "the wrench only";
      EXPECT_FALSE(stats.paused);
      const std::vector<TimedState> seen = client.states();
      for (std::size_t i = 1; i < seen.size(); ++i)
        EXPECT_GT(seen[i].state.tick, seen[i - 1].state.tick) << "a refused reset took effect";
      for (const TimedState& s : seen)
        EXPECT_EQ(s.state.position[2], 0.0) << "a refused edit took effect";
    } else {
      EXPECT_EQ(stats.rejected.not_permitted, 0);
      // Paused by the handshake, rigidd published the edited state before answering (the reset
      // sent after it put the brick back).
      const std::vector<TimedState> seen = client.states();
      EXPECT_TRUE(std::any_of(seen.begin(), seen.end(), [](const TimedState& s) {
        return s.state.position[2] == 5.0;
      })) << "the edit never showed";
    }
    EXPECT_EQ(daemon.terminate(2000ms), 0) << daemon.stderr_text();
  }
}

INSTANTIATE_TEST_SUITE_P(Bus, ControlsFlag, ::testing::Values(Bus::kDds, Bus::kLcm),
                         [](const ::testing::TestParamInfo<Bus>& info) {
                           return std::string(info.param == Bus::kDds ? "Dds" : "Lcm");
                         });

}  // namespace
}  // namespace rigid::rigidd::testing
