// Each reason a command from the network is refused for, and what passes.
#include "loop/command_validation.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <string>
#include <vector>

#include "loop/sequence_table.hpp"

namespace rigid::loop {
namespace {

using rigid::ControlCommand;
using rigid::ControlKind;
using rigid::WrenchCommand;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

class Validation : public ::testing::Test {
 protected:
  Validation() : bodies_({"box", "ball", "arm/link.1"}), validator_(bodies_, limits()) {}
  static scene::Limits limits() {
    scene::Limits l;
    l.max_force = 100;
    l.max_torque = 10;
    l.max_ttl = 5;
    return l;
  }
  static WrenchCommand good() {
    WrenchCommand w;
    w.source = 7;
    w.seq = 1;
    w.body_id = 1;
    w.force = {3, 4, 0};
    w.point = {0.1, 0, 0};
    w.force_frame = rigid::Frame::kBody;
    w.torque = {0, 0, 1};
    w.ttl = 0.5;
    return w;
  }
  RejectReason reason(const WrenchCommand& w) {
    const Checked<Wrench> c = validator_.check(w);
    EXPECT_FALSE(c.ok);
    EXPECT_FALSE(c.detail.empty());
    return c.reason;
  }
  BodyDirectory bodies_;
  CommandValidator validator_;
};

// Every name is found at its id, in a directory given its names out of order; prefixes, extensions
// and near misses of a name are not found.
TEST(BodyDirectoryFind, EveryNameAtItsIdAndNothingElse) {
  std::vector<std::string> names;
  for (int i = 0; i < 1000; ++i)
    names.push_back("b" + std::to_string((i * 7919) % 1000));  // b0, b919, b838, ...
  names.emplace_back("");
  names.emplace_back("arm/link.1");
  const BodyDirectory bodies(names);
  ASSERT_EQ(bodies.size(), static_cast<int>(names.size()));
  for (int id = 0; id < bodies.size(); ++id) {
    EXPECT_EQ(bodies.find(names[static_cast<std::size_t>(id)]), id) << names[id];
    EXPECT_EQ(bodies.name(id), names[static_cast<std::size_t>(id)]);
  }
  for (const char* absent : {"b", "b1000", "b01", "a", "c", "arm/link.", "arm/link.10", " b1"})
    EXPECT_EQ(bodies.find(absent), -1) << absent;
}

TEST_F(Validation, AGoodWrenchPassesWithItsFields) {
  const Checked<Wrench> c = validator_.check(good());
  ASSERT_TRUE(c.ok) << c.detail;
  EXPECT_EQ(c.value.body, 1);
  EXPECT_EQ(c.value.source, 7);
  EXPECT_EQ(c.value.force, (Vec3{3, 4, 0}));
  EXPECT_EQ(c.value.force_frame, rigid::Frame::kBody);
  EXPECT_EQ(c.value.ttl, 0.5);
}

TEST_F(Validation, BodiesAreFoundByIdOrName) {
  WrenchCommand w = good();
  w.body_id = -1;
  w.body_name = "arm/link.1";
  Checked<Wrench> c = validator_.check(w);
  ASSERT_TRUE(c.ok);
  EXPECT_EQ(c.value.body, 2);
  w.body_name = "box";
  EXPECT_EQ(validator_.check(w).value.body, 0);
}

TEST_F(Validation, NonFiniteNumbers) {
  for (int field = 0; field < 4; ++field) {
    for (double bad : {kNaN, kInf, -kInf}) {
      WrenchCommand w = good();
      if (field == 0) w.force[1] = bad;
      if (field == 1) w.point[2] = bad;
      if (field == 2) w.torque[0] = bad;
      if (field == 3) w.ttl = bad;
      EXPECT_EQ(reason(w), RejectReason::kNonFinite) << field;
    }
  }
}

TEST_F(Validation, UnknownBodies) {
  WrenchCommand w = good();
  w.body_id = 3;
  EXPECT_EQ(reason(w), RejectReason::kUnknownBody);
  w.body_id = -1;
  w.body_name = "nobody";
  EXPECT_EQ(reason(w), RejectReason::kUnknownBody);
  w.body_name = "";
  EXPECT_EQ(reason(w), RejectReason::kUnknownBody);
  w.body_name = std::string("box\0x", 5);  // not "box"
  EXPECT_EQ(reason(w), RejectReason::kUnknownBody);
}

TEST_F(Validation, OverLimits) {
  WrenchCommand w = good();
  w.force = {60, 80, 0.001};  // |f| just over 100
  EXPECT_EQ(reason(w), RejectReason::kOverLimit);
  w = good();
  w.torque = {0, 0, 10.5};
  EXPECT_EQ(reason(w), RejectReason::kOverLimit);
  w = good();
  w.point = {0, 0, 1};  // |r x f| = 5
  EXPECT_TRUE(validator_.check(w).ok);
  w.point = {0, 0, 3};  // |r x f| = 15 > max_torque 10
  EXPECT_EQ(reason(w), RejectReason::kOverLimit);
  w = good();
  w.ttl = 5.01;
  EXPECT_EQ(reason(w), RejectReason::kOverLimit);
  w.ttl = 5.0;
  EXPECT_TRUE(validator_.check(w).ok);
}

TEST_F(Validation, InvalidFields) {
  WrenchCommand w = good();
  w.force_frame = static_cast<rigid::Frame>(2);
  EXPECT_EQ(reason(w), RejectReason::kInvalid);
  w = good();
  w.torque_frame = static_cast<rigid::Frame>(-1);
  EXPECT_EQ(reason(w), RejectReason::kInvalid);
  w = good();
  w.ttl = -0.1;
  EXPECT_EQ(reason(w), RejectReason::kInvalid);
}

TEST_F(Validation, Controls) {
  ReplyNote note{};
  ControlCommand c;
  c.source = 1;
  c.seq = 1;
  for (ControlKind k : {ControlKind::kPause, ControlKind::kResume, ControlKind::kReset}) {
    c.command = k;
    EXPECT_TRUE(validator_.check(c, &note).ok);
  }
  c.command = ControlKind::kStep;
  c.steps = 0;
  Checked<Control> r = validator_.check(c, &note);
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.reason, RejectReason::kInvalid);
  EXPECT_EQ(note, ReplyNote::kBadSteps);
  c.steps = 10;
  EXPECT_TRUE(validator_.check(c, &note).ok);

  c.command = ControlKind::kSetRtf;
  c.rtf = kNaN;
  r = validator_.check(c, &note);
  EXPECT_EQ(r.reason, RejectReason::kNonFinite);
  EXPECT_EQ(note, ReplyNote::kNonFinite);
  c.rtf = 0;
  EXPECT_EQ(validator_.check(c, &note).reason, RejectReason::kInvalid);
  c.rtf = 2;
  EXPECT_TRUE(validator_.check(c, &note).ok);

  c.command = ControlKind::kNone;
  EXPECT_FALSE(validator_.check(c, &note).ok);
  EXPECT_EQ(note, ReplyNote::kUnknownCommand);
  c.command = static_cast<ControlKind>(42);
  EXPECT_FALSE(validator_.check(c, &note).ok);
}

rigid::EditCommand good_edit() {
  rigid::EditCommand e;
  e.source = 7;
  e.seq = 3;
  e.kind = rigid::EditKind::kSetState;
  e.body_id = -1;
  e.body_name = "arm/link.1";
  e.set = rigid::kSetAll;
  e.position = {1, 2, 3};
  e.orientation = {0.5, 0.5, -0.5, 0.5};
  e.linear_velocity = {0, 0, 1};
  e.velocity_frame = rigid::Frame::kBody;
  e.angular_velocity = {0, 2, 0};
  e.stamp_ns = 99;
  return e;
}

TEST_F(Validation, AGoodEditPassesWithWhatItSets) {
  Checked<Edit> c = validator_.check(good_edit());
  ASSERT_TRUE(c.ok) << c.detail;
  EXPECT_EQ(c.value.body, 2);
  EXPECT_EQ(c.value.kind, rigid::EditKind::kSetState);
  EXPECT_EQ(c.value.state_edit(), good_edit().state_edit());
  EXPECT_EQ(c.value.source, 7);
  EXPECT_EQ(c.value.seq, 3);
  EXPECT_EQ(c.value.stamp_ns, 99);

  // Only the parts set travel on; those not set are not looked at (a NaN there passes).
  rigid::EditCommand p = good_edit();
  p.set = rigid::kSetPosition;
  p.linear_velocity = {kNaN, 0, 0};
  p.orientation = {0, 0, 0, 0};
  p.velocity_frame = static_cast<rigid::Frame>(9);
  c = validator_.check(p);
  ASSERT_TRUE(c.ok) << c.detail;
  EXPECT_EQ(c.value.position, p.position);
  EXPECT_EQ(c.value.linear_velocity, (rigid::Vec3{}));
  EXPECT_EQ(c.value.orientation, (rigid::StateEdit{}.orientation));

  // A reset names a body and nothing else.
  rigid::EditCommand r = good_edit();
  r.kind = rigid::EditKind::kResetBody;
  r.body_id = 0;
  r.position = {kInf, 0, 0};
  c = validator_.check(r);
  ASSERT_TRUE(c.ok) << c.detail;
  EXPECT_EQ(c.value.body, 0);
  EXPECT_EQ(c.value.set, 0);
  // A quaternion typed with four decimals is within the tolerance.
  rigid::EditCommand typed = good_edit();
  typed.orientation = {0.7071, 0, 0, 0.7071};
  EXPECT_TRUE(validator_.check(typed).ok);
}

TEST_F(Validation, EditRefusals) {
  const auto refused = [&](const rigid::EditCommand& e) {
    const Checked<Edit> c = validator_.check(e);
    EXPECT_FALSE(c.ok);
    EXPECT_NE(c.detail.find("edit from source 7 seq 3: "), std::string::npos) << c.detail;
    return c.reason;
  };
  rigid::EditCommand e = good_edit();
  e.kind = rigid::EditKind::kNone;
  EXPECT_EQ(refused(e), RejectReason::kInvalid);
  e.kind = static_cast<rigid::EditKind>(3);  // spawn is not (yet) a kind
  EXPECT_EQ(refused(e), RejectReason::kInvalid);

  e = good_edit();
  e.position[1] = kNaN;
  EXPECT_EQ(refused(e), RejectReason::kNonFinite);
  e = good_edit();
  e.orientation[3] = kInf;
  EXPECT_EQ(refused(e), RejectReason::kNonFinite);
  e = good_edit();
  e.linear_velocity[0] = -kInf;
  EXPECT_EQ(refused(e), RejectReason::kNonFinite);
  e = good_edit();
  e.angular_velocity[2] = kNaN;
  EXPECT_EQ(refused(e), RejectReason::kNonFinite);

  e = good_edit();
  e.body_name = "arm/link.2";
  EXPECT_EQ(refused(e), RejectReason::kUnknownBody);
  e = good_edit();
  e.body_id = 3;
  EXPECT_EQ(refused(e), RejectReason::kUnknownBody);
  e.kind = rigid::EditKind::kResetBody;
  EXPECT_EQ(refused(e), RejectReason::kUnknownBody);

  e = good_edit();
  e.set = 0;
  EXPECT_EQ(refused(e), RejectReason::kInvalid);
  e.set = 16;
  EXPECT_EQ(refused(e), RejectReason::kInvalid);
  e.set = -1;
  EXPECT_EQ(refused(e), RejectReason::kInvalid);
  e = good_edit();
  e.velocity_frame = static_cast<rigid::Frame>(2);
  EXPECT_EQ(refused(e), RejectReason::kInvalid);
  e = good_edit();
  e.angular_velocity_frame = static_cast<rigid::Frame>(-1);
  EXPECT_EQ(refused(e), RejectReason::kInvalid);
  // Not a unit quaternion: a zero one, one off by more than 1e-3.
  e = good_edit();
  e.orientation = {0, 0, 0, 0};
  EXPECT_EQ(refused(e), RejectReason::kInvalid);
  e.orientation = {1.002, 0, 0, 0};
  EXPECT_EQ(refused(e), RejectReason::kInvalid);
  const Checked<Edit> c = validator_.check(e);
  EXPECT_NE(c.detail.find("orientation (1.002, 0, 0, 0): |q| 1.002 is not 1"), std::string::npos)
      << c.detail;
}

TEST(SequenceTable, BackwardsAndRepeatedSequencesAreStale) {
  SequenceTable t(4);
  std::int64_t last = 0;
  EXPECT_TRUE(t.accept(1, 5, &last));
  EXPECT_TRUE(t.accept(1, 6, &last));
  EXPECT_FALSE(t.accept(1, 6, &last));
  EXPECT_EQ(last, 6);
  EXPECT_FALSE(t.accept(1, 2, &last));
  EXPECT_TRUE(t.accept(2, 1, &last));    // other sources are independent
  EXPECT_TRUE(t.accept(1, 100, &last));  // gaps are fine
}

TEST(SequenceTable, WhenFullTheLeastRecentSourceIsForgotten) {
  SequenceTable t(2);
  std::int64_t last = 0;
  t.accept(1, 10, &last);
  t.accept(2, 10, &last);
  t.accept(1, 11, &last);  // source 2 is now the least recent
  t.accept(3, 10, &last);  // evicts 2
  EXPECT_EQ(t.size(), 2u);
  EXPECT_FALSE(t.accept(1, 5, &last));  // 1 is remembered
  EXPECT_TRUE(t.accept(2, 5, &last));   // 2 was forgotten
}

}  // namespace
}  // namespace rigid::loop
