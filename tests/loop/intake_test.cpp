// The intake (a transport's receiver): valid commands are queued, refusals counted by reason and
// the first of each kept for the log, a full queue counts drops, a refused control is answered.
#include "loop/intake.hpp"

#include <gtest/gtest.h>

#include <mutex>
#include <variant>
#include <vector>

namespace rigid::loop {
namespace {

class Replies final : public ReplySink {
 public:
  void reply(const Reply& r) override {
    const std::lock_guard lock(mutex_);
    replies.push_back(r);
  }
  std::mutex mutex_;
  std::vector<Reply> replies;
};

class IntakeTest : public ::testing::Test {
 protected:
  IntakeTest()
      : bodies_({"a", "b"}),
        validator_(bodies_, scene::Limits{}),
        queue_(4),
        intake_(rigid::Bus::kLcm, validator_, IntakePolicy{}, queue_, doorbell_, rejects_,
                replies_) {}

  static transport::Origin session(std::uint64_t s) {
    transport::Origin o;
    o.session = s;
    return o;
  }

  static rigid::WrenchCommand wrench(std::int64_t seq) {
    rigid::WrenchCommand w;
    w.source = 1;
    w.seq = seq;
    w.body_id = 0;
    w.force = {1, 0, 0};
    return w;
  }

  BodyDirectory bodies_;
  CommandValidator validator_;
  BoundedQueue<Command> queue_;
  Doorbell doorbell_;
  RejectCounters rejects_;
  Replies replies_;
  Intake intake_;
};

TEST_F(IntakeTest, ValidCommandsAreQueuedWithTheirBusAndRingTheDoorbell) {
  const std::uint32_t before = doorbell_.count();
  intake_.on_wrench(wrench(1), session(7));
  rigid::ControlCommand c;
  c.source = 2;
  c.seq = 1;
  c.command = rigid::ControlKind::kPause;
  intake_.on_control(c, session(7));
  EXPECT_EQ(doorbell_.count(), before + 2);
  Command out;
  ASSERT_TRUE(queue_.try_pop(out));
  ASSERT_TRUE(std::holds_alternative<Wrench>(out.what));
  EXPECT_EQ(out.bus, rigid::Bus::kLcm);
  EXPECT_EQ(std::get<Wrench>(out.what).seq, 1);
  ASSERT_TRUE(queue_.try_pop(out));
  ASSERT_TRUE(std::holds_alternative<Control>(out.what));
  EXPECT_EQ(std::get<Control>(out.what).kind, rigid::ControlKind::kPause);
  EXPECT_EQ(rejects_.total(), 0);
}

TEST_F(IntakeTest, RefusalsAreCountedByReasonAndTheFirstOfEachIsLogged) {
  rigid::WrenchCommand w = wrench(1);
  w.force[0] = std::numeric_limits<double>::quiet_NaN();
  intake_.on_wrench(w, session(7));
  intake_.on_wrench(w, session(7));
  w = wrench(2);
  w.body_id = 9;
  intake_.on_wrench(w, session(7));
  w = wrench(3);
  w.force = {2e6, 0, 0};
  intake_.on_wrench(w, session(7));
  intake_.on_decode_error(
      {rigid::Bus::kLcm, transport::Topic::kWrench, transport::DecodeStatus::kTruncated, 5});
  const rigid::RejectCounts c = rejects_.counts();
  EXPECT_EQ(c.non_finite, 2);
  EXPECT_EQ(c.unknown_body, 1);
  EXPECT_EQ(c.over_limit, 1);
  EXPECT_EQ(c.undecodable, 1);
  Command out;
  EXPECT_FALSE(queue_.try_pop(out));  // none reached the loop

  MemoryLog log;
  rejects_.flush(log, 0);
  const std::vector<std::string> lines = log.lines();
  // One per reason, and one line summing up the rest (the second non-finite one).
  ASSERT_EQ(lines.size(), 5u);
  EXPECT_NE(lines[0].find("rejected non_finite: wrench from source 1 seq 1: force (nan"),
            std::string::npos)
      << lines[0];
  EXPECT_NE(lines[3].find("undecodable: lcm payload on wrench (5 bytes): truncated"),
            std::string::npos)
      << lines[3];
  EXPECT_NE(lines[4].find("refused 1 command(s) since the last report (non_finite 1); most from "
                          "lcm:0.0.0.0:7"),
            std::string::npos)
      << lines[4];
  rejects_.flush(log, 500'000'000);
  EXPECT_EQ(log.lines().size(), 5u);  // logged once
  // Counted by sender, too (the undecodable payload has none).
  const std::vector<rigid::SourceRefusals> top = rejects_.top_senders();
  ASSERT_EQ(top.size(), 1u);
  EXPECT_EQ(top[0].sender, "lcm:0.0.0.0:7");
  EXPECT_EQ(top[0].count, 4);
  EXPECT_EQ(top[0].last_reason, "over_limit");
}

TEST_F(IntakeTest, AFloodFillsTheQueueAndDropsAreCounted) {
  for (int i = 1; i <= 10; ++i)
    intake_.on_wrench(wrench(i), session(7));
  EXPECT_EQ(rejects_.counts().queue_full, 10 - 4);
  // Each dropped wrench is answered, at most RejectCounters::kRepliesPerSecond a second.
  ASSERT_EQ(replies_.replies.size(), static_cast<std::size_t>(RejectCounters::kRepliesPerSecond));
  EXPECT_EQ(replies_.replies[0].kind, rigid::kReplyToWrench);
  EXPECT_EQ(replies_.replies[0].seq, 5);
  EXPECT_NE(reply_message(replies_.replies[0]).find("queue_full: command queue full (4)"),
            std::string::npos)
      << reply_message(replies_.replies[0]);
  replies_.replies.clear();
  rigid::ControlCommand c;
  c.source = 2;
  c.seq = 1;
  c.command = rigid::ControlKind::kReset;
  intake_.on_control(c, session(7));
  EXPECT_EQ(rejects_.counts().queue_full, 10 - 4 + 1);
  // A dropped control is still answered.
  ASSERT_EQ(replies_.replies.size(), 1u);
  EXPECT_EQ(replies_.replies[0].outcome, rigid::Outcome::kFailed);
  EXPECT_EQ(replies_.replies[0].note, ReplyNote::kQueueFull);
}

TEST_F(IntakeTest, ARefusedControlIsAnsweredOnItsBus) {
  rigid::ControlCommand c;
  c.source = 5;
  c.seq = 77;
  c.command = rigid::ControlKind::kStep;
  c.steps = -3;
  intake_.on_control(c, session(7));
  ASSERT_EQ(replies_.replies.size(), 1u);
  const Reply& r = replies_.replies[0];
  EXPECT_EQ(r.bus, rigid::Bus::kLcm);
  EXPECT_EQ(r.seq, 77);
  EXPECT_EQ(r.source, 5);
  EXPECT_EQ(r.outcome, rigid::Outcome::kInvalid);
  EXPECT_EQ(reply_message(r), "steps must be >= 1 and <= 1000000000");
  EXPECT_EQ(rejects_.counts().invalid, 1);
}

TEST_F(IntakeTest, ASenderAboveItsRateIsRefusedAndOthersAreNot) {
  scene::Limits limits;
  limits.max_commands_per_second = 100;  // a burst of 50 passes at once
  CommandValidator validator(bodies_, limits);
  IntakePolicy policy;
  policy.commands_per_second = limits.max_commands_per_second;
  BoundedQueue<Command> queue(1000);
  Intake intake(rigid::Bus::kDds, validator, policy, queue, doorbell_, rejects_, replies_);
  for (int i = 1; i <= 80; ++i)
    intake.on_wrench(wrench(i), session(1));
  EXPECT_GE(rejects_.counts().rate_limited, 29);  // 80 - 50, less what the clock refilled
  EXPECT_LE(rejects_.counts().rate_limited, 30);
  // Another session (a restarted controller, another process) has its own share.
  for (int i = 1; i <= 50; ++i)
    intake.on_wrench(wrench(i), session(2));
  EXPECT_LE(rejects_.counts().rate_limited, 30);
  const std::vector<rigid::SourceRefusals> top = rejects_.top_senders();
  ASSERT_EQ(top.size(), 1u);
  EXPECT_EQ(top[0].sender, "dds:0000000000000001");
  EXPECT_EQ(top[0].last_reason, "rate_limited");
}

TEST_F(IntakeTest, ControlsOffAreRefusedAndAnswered) {
  IntakePolicy policy;
  policy.controls = false;
  Intake intake(rigid::Bus::kLcm, validator_, policy, queue_, doorbell_, rejects_, replies_);
  rigid::ControlCommand c;
  c.source = 2;
  c.seq = 1;
  c.command = rigid::ControlKind::kPause;
  intake.on_control(c, session(3));
  Command out;
  EXPECT_FALSE(queue_.try_pop(out));
  EXPECT_EQ(rejects_.counts().not_permitted, 1);
  ASSERT_EQ(replies_.replies.size(), 1u);
  EXPECT_EQ(replies_.replies[0].outcome, rigid::Outcome::kNotAllowed);
  EXPECT_EQ(replies_.replies[0].note, ReplyNote::kNotPermitted);
  // Wrenches still pass.
  intake.on_wrench(wrench(1), session(3));
  EXPECT_TRUE(queue_.try_pop(out));
}

TEST_F(IntakeTest, WithSecurityOnlyAnAuthenticatedWriterOfThatBodyPushesIt) {
  IntakePolicy policy;
  policy.secure = true;
  Intake intake(rigid::Bus::kDds, validator_, policy, queue_, doorbell_, rejects_, replies_);
  transport::Origin plain = session(4);  // no identity: not from a push/IDENTITY/BODY writer
  intake.on_wrench(wrench(1), plain);
  transport::Origin alice = session(5);
  alice.authenticated = true;
  alice.identity = "alice";
  alice.permitted_body = "b";
  intake.on_wrench(wrench(2), alice);  // body 0 is "a"
  EXPECT_EQ(rejects_.counts().not_permitted, 2);
  Command out;
  EXPECT_FALSE(queue_.try_pop(out));
  rigid::WrenchCommand to_b = wrench(3);
  to_b.body_id = 1;
  intake.on_wrench(to_b, alice);
  ASSERT_TRUE(queue_.try_pop(out));
  EXPECT_EQ(std::string(out.sender.name), "alice");
  EXPECT_NE(std::get<Wrench>(out.what).owner, 0u);
  // Two sessions of one identity share its key; another identity has another.
  transport::Origin alice2 = alice;
  alice2.session = 6;
  transport::Origin bob = alice;
  bob.identity = "bob";
  EXPECT_EQ(sender_of(rigid::Bus::kDds, alice).key, sender_of(rigid::Bus::kDds, alice2).key);
  EXPECT_NE(sender_of(rigid::Bus::kDds, alice).key, sender_of(rigid::Bus::kDds, bob).key);
  EXPECT_NE(owner_of(alice), owner_of(bob));
}

}  // namespace
}  // namespace rigid::loop
