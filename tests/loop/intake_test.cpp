// The intake (a transport's receiver): valid commands are queued, refusals counted by reason and
// the first of each kept for the log, a full queue counts drops, a refused control is answered.
#include "loop/intake.hpp"

#include <gtest/gtest.h>

#include <mutex>
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
        intake_(transport::Bus::kLcm, validator_, queue_, doorbell_, rejects_, replies_) {}

  static transport::WrenchCommand wrench(std::int64_t seq) {
    transport::WrenchCommand w;
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
  intake_.on_wrench(wrench(1));
  transport::ControlCommand c;
  c.source = 2;
  c.seq = 1;
  c.command = transport::ControlKind::kPause;
  intake_.on_control(c);
  EXPECT_EQ(doorbell_.count(), before + 2);
  Command out;
  ASSERT_TRUE(queue_.try_pop(out));
  EXPECT_EQ(out.kind, Command::Kind::kWrench);
  EXPECT_EQ(out.bus, transport::Bus::kLcm);
  EXPECT_EQ(out.wrench.seq, 1);
  ASSERT_TRUE(queue_.try_pop(out));
  EXPECT_EQ(out.kind, Command::Kind::kControl);
  EXPECT_EQ(out.control.kind, transport::ControlKind::kPause);
  EXPECT_EQ(rejects_.total(), 0);
}

TEST_F(IntakeTest, RefusalsAreCountedByReasonAndTheFirstOfEachIsLogged) {
  transport::WrenchCommand w = wrench(1);
  w.force[0] = std::numeric_limits<double>::quiet_NaN();
  intake_.on_wrench(w);
  intake_.on_wrench(w);
  w = wrench(2);
  w.body_id = 9;
  intake_.on_wrench(w);
  w = wrench(3);
  w.force = {2e6, 0, 0};
  intake_.on_wrench(w);
  intake_.on_decode_error(
      {transport::Bus::kLcm, transport::Topic::kWrench, transport::DecodeStatus::kTruncated, 5});
  const transport::RejectCounts c = rejects_.counts();
  EXPECT_EQ(c.non_finite, 2);
  EXPECT_EQ(c.unknown_body, 1);
  EXPECT_EQ(c.over_limit, 1);
  EXPECT_EQ(c.undecodable, 1);
  Command out;
  EXPECT_FALSE(queue_.try_pop(out));  // none reached the loop

  MemoryLog log;
  rejects_.flush(log);
  const std::vector<std::string> lines = log.lines();
  ASSERT_EQ(lines.size(), 4u);  // one per reason, not per refusal
  EXPECT_NE(lines[0].find("rejected non_finite: wrench from source 1 seq 1: force (nan"),
            std::string::npos)
      << lines[0];
  EXPECT_NE(lines[3].find("undecodable: lcm payload on wrench (5 bytes): truncated"),
            std::string::npos)
      << lines[3];
  rejects_.flush(log);
  EXPECT_EQ(log.lines().size(), 4u);  // logged once
}

TEST_F(IntakeTest, AFloodFillsTheQueueAndDropsAreCounted) {
  for (int i = 1; i <= 10; ++i)
    intake_.on_wrench(wrench(i));
  EXPECT_EQ(rejects_.counts().queue_full, 10 - 4);
  transport::ControlCommand c;
  c.source = 2;
  c.seq = 1;
  c.command = transport::ControlKind::kReset;
  intake_.on_control(c);
  EXPECT_EQ(rejects_.counts().queue_full, 10 - 4 + 1);
  // A dropped control is still answered.
  ASSERT_EQ(replies_.replies.size(), 1u);
  EXPECT_EQ(replies_.replies[0].outcome, transport::Outcome::kFailed);
  EXPECT_EQ(replies_.replies[0].note, ReplyNote::kQueueFull);
}

TEST_F(IntakeTest, ARefusedControlIsAnsweredOnItsBus) {
  transport::ControlCommand c;
  c.source = 5;
  c.seq = 77;
  c.command = transport::ControlKind::kStep;
  c.steps = -3;
  intake_.on_control(c);
  ASSERT_EQ(replies_.replies.size(), 1u);
  const Reply& r = replies_.replies[0];
  EXPECT_EQ(r.bus, transport::Bus::kLcm);
  EXPECT_EQ(r.seq, 77);
  EXPECT_EQ(r.source, 5);
  EXPECT_EQ(r.outcome, transport::Outcome::kInvalid);
  EXPECT_EQ(reply_message(r), "steps must be >= 1 and <= 1000000000");
  EXPECT_EQ(rejects_.counts().invalid, 1);
}

}  // namespace
}  // namespace rigid::loop
