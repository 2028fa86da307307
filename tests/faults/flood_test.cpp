// A flood of commands (10^5 valid wrenches a second for 2 s) on each bus: rigidd stays alive,
// answers a control request sent in the middle of it, and accounts for every command it received
// (accepted, or refused and counted by reason: accepted + refused = received, exactly). What the
// bus itself loses before rigidd sees it (a UDP socket buffer overrun, a DDS reader history of 256
// overwritten) is rigidd's to neither see nor count: bench/loop/flood_bench.cpp measures it, with the loop's
// timing. Runs alone (RUN_SERIAL): the flood takes both cores and would disturb timed tests.
#include <gtest/gtest.h>

#include <atomic>
#include <string>
#include <thread>
#include <vector>

#include "fault_rig.hpp"

namespace rigid::faults::testing {
namespace {

// Every command received (decoded) is accepted or refused for one reason (undecodable payloads
// are counted apart: they were never received as commands).
std::int64_t accounted(const rigid::StatsReport& s) {
  const rigid::RejectCounts& r = s.rejected;
  return s.commands_accepted + r.non_finite + r.unknown_body + r.over_limit + r.stale_sequence +
         r.queue_full + r.invalid + r.over_share + r.rate_limited + r.not_permitted;
}

std::int64_t received(const rigid::StatsReport& s, Bus bus) {
  return bus == Bus::kDds ? s.dds.received : s.lcm.received;
}

class Flood : public ::testing::TestWithParam<Bus> {};

TEST_P(Flood, EveryCommandReceivedIsAccountedForAndRigiddStaysResponsive) {
  const Bus bus = GetParam();
  Rig rig(bus, kDefault);
  ASSERT_TRUE(rig.handshake()) << rig.daemon->stderr_text();
  BusClient flooder(bus, rig.prefix());
  rigid::ControlCommand harmless;
  harmless.command = rigid::ControlKind::kSetRtf;
  harmless.rtf = 1.0;
  ASSERT_TRUE(flooder.handshake(harmless, 10s));
  const auto before = rig.stats_after(rig.monitor->last_state()->state.tick);
  ASSERT_TRUE(before);

  std::atomic<std::int64_t> sent{0};
  const auto t0 = std::chrono::steady_clock::now();
  const auto end = t0 + 2s;
  std::thread flood([&] {
    rigid::WrenchCommand w;
    std::int64_t n = 0;
    for (auto now = t0; now < end; now = std::chrono::steady_clock::now()) {
      const auto due = std::chrono::duration_cast<std::chrono::microseconds>(now - t0).count() / 10;
      for (; n < due; ++n) {
        w.body_id = static_cast<std::int32_t>(n % 5);
        w.key = static_cast<std::int32_t>(n % 4);
        w.force = {0, 0, 0.5};
        flooder.send(w);
      }
      std::this_thread::sleep_for(100us);
    }
    sent = n;
  });
  // A control sent mid-flood is answered. LCM is UDP and every socket on its group gets the
  // flood: rigidd's drops a share of the controls on their way in, and the monitor's a share of
  // the replies on their way back, under ASan at times every one while the flood lasts. So, as a
  // controller on a lossy bus would, the test asks again, every 150 ms (an answer takes
  // milliseconds) while the flood lasts; and a reply the monitor's socket dropped counts when
  // rigidd's log shows it answered that request (it logs each reply it sends).
  std::this_thread::sleep_until(t0 + 500ms);
  std::optional<rigid::ControlReply> reply;
  std::vector<std::int64_t> asked;
  while (!reply && std::chrono::steady_clock::now() + 150ms < end) {
    std::int64_t seq = 0;
    reply = rig.monitor->request(harmless, 150ms, &seq);
    asked.push_back(seq);
  }
  flood.join();
  std::string answer;  // the outcome and message, as a reply or as rigidd logged it
  if (reply) {
    answer = reply->outcome == rigid::Outcome::kOk ? "ok" : reply->message;
  } else {
    const std::string log = rig.daemon->stderr_text();
    for (const std::int64_t seq : asked) {
      const std::string line = "from source " + std::to_string(rig.monitor->source()) + " seq " +
                               std::to_string(seq) + " (" + (bus == Bus::kDds ? "dds" : "lcm") +
                               "): ";
      const std::size_t at = log.find(line);
      if (at == std::string::npos) continue;
      const std::size_t from = at + line.size();
      answer = log.substr(from, log.find('\n', from) - from);
      break;
    }
  }
  ASSERT_FALSE(answer.empty()) << "no answer to " << asked.size() << " controls during the flood, "
                               << "neither received nor in rigidd's log";
  // Answered either way: carried out, or dropped with the queue full (and counted).
  EXPECT_TRUE(answer == "ok" || answer.starts_with("ok at tick") ||
              answer.find("dropped: the command queue is full") != std::string::npos ||
              answer.find("refused: this sender is above its share") != std::string::npos)
      << answer;

  // Once rigidd has taken in what was on its way, the counts settle and add up.
  std::optional<rigid::StatsReport> after = rig.stats_after(before->tick);
  ASSERT_TRUE(after);
  for (int i = 0; i < 6; ++i) {
    const auto next = rig.stats_after(after->tick);
    ASSERT_TRUE(next) << "rigidd stopped publishing Stats after the flood";
    const bool settled = received(*next, bus) == received(*after, bus);
    after = next;
    if (settled) break;
  }
  const std::int64_t got = received(*after, bus) - received(*before, bus);
  EXPECT_GT(got, sent / 10) << "hardly any of the flood reached rigidd";
  EXPECT_LE(got, sent + static_cast<std::int64_t>(asked.size()));  // the flood and the controls
  EXPECT_EQ(accounted(*after) - accounted(*before), got)
      << "accepted " << after->commands_accepted - before->commands_accepted << ", queue_full "
      << after->rejected.queue_full - before->rejected.queue_full << ", rate_limited "
      << after->rejected.rate_limited - before->rejected.rate_limited;
  // One sender flooding: it is held to its share of the command rate (limits), the rest refused.
  EXPECT_GT(after->rejected.rate_limited - before->rejected.rate_limited, got / 2);
  EXPECT_EQ(after->rejected.non_finite + after->rejected.invalid + after->rejected.unknown_body, 0);

  // Still ticking and publishing.
  const std::int64_t tick = rig.monitor->last_state()->state.tick;
  EXPECT_TRUE(rig.monitor->wait(
      [&] { return rig.monitor->states_locked().back().state.tick > tick + 100; }, 2s));
  EXPECT_EQ(rig.daemon->terminate(1000ms), 0) << rig.daemon->stderr_text();
}

INSTANTIATE_TEST_SUITE_P(Bus, Flood, ::testing::Values(Bus::kDds, Bus::kLcm), param_name);

}  // namespace
}  // namespace rigid::faults::testing
