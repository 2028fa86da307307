// The wrench table: replace by (source, body, key), expiry by time to live, capacity, order.
#include "common/wrench_table.hpp"

#include <gtest/gtest.h>

namespace rigid::loop {
namespace {

Wrench wrench(std::int64_t source, std::int32_t body, std::int32_t key, double fx) {
  Wrench w;
  w.source = source;
  w.body = body;
  w.key = key;
  w.force = {fx, 0, 0};
  return w;
}

TEST(TicksToLive, RoundsUpButForgivesRoundOff) {
  EXPECT_EQ(common::ticks_to_live(0.0, 1e-3), 1);    // 0: this tick only
  EXPECT_EQ(common::ticks_to_live(0.2, 1e-3), 200);  // 0.2 / 0.001 = 200.00000000000003
  EXPECT_EQ(common::ticks_to_live(0.0015, 1e-3), 2);
  EXPECT_EQ(common::ticks_to_live(1e-9, 1e-3), 1);
  EXPECT_EQ(common::ticks_to_live(60.0, 1.0 / 240), 14400);
}

TEST(WrenchTable, SameKeyReplacesInPlace) {
  common::WrenchTable t(8);
  EXPECT_EQ(t.upsert(wrench(1, 0, 0, 1.0), 0, SIZE_MAX, 10),
            common::WrenchTable::Upsert::kInserted);
  EXPECT_EQ(t.upsert(wrench(2, 0, 0, 2.0), 0, SIZE_MAX, 10),
            common::WrenchTable::Upsert::kInserted);
  EXPECT_EQ(t.upsert(wrench(1, 0, 0, 3.0), 0, SIZE_MAX, 20),
            common::WrenchTable::Upsert::kReplaced);
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t.active()[0].wrench.force[0], 3.0);  // kept its place
  EXPECT_EQ(t.active()[0].expires_at_tick, 20);
  EXPECT_EQ(t.active()[1].wrench.force[0], 2.0);
}

TEST(WrenchTable, DifferentSourceBodyOrKeyAreDifferentEntries) {
  common::WrenchTable t(8);
  t.upsert(wrench(1, 0, 0, 1.0), 0, SIZE_MAX, 10);
  t.upsert(wrench(1, 1, 0, 1.0), 0, SIZE_MAX, 10);
  t.upsert(wrench(1, 0, 1, 1.0), 0, SIZE_MAX, 10);
  t.upsert(wrench(2, 0, 0, 1.0), 0, SIZE_MAX, 10);
  EXPECT_EQ(t.size(), 4u);
}

TEST(WrenchTable, EntriesExpireWhenTheTickReachesTheirEnd) {
  common::WrenchTable t(8);
  t.upsert(wrench(1, 0, 0, 1.0), 0, SIZE_MAX, 3);
  t.upsert(wrench(2, 0, 0, 2.0), 0, SIZE_MAX, 5);
  t.upsert(wrench(3, 0, 0, 3.0), 0, SIZE_MAX, 4);
  EXPECT_EQ(t.expire(2), 0u);
  EXPECT_EQ(t.expire(3), 1u);
  ASSERT_EQ(t.size(), 2u);
  // Survivors keep their order, and stay findable after moving.
  EXPECT_EQ(t.active()[0].wrench.source, 2);
  EXPECT_EQ(t.active()[1].wrench.source, 3);
  EXPECT_EQ(t.upsert(wrench(3, 0, 0, 30.0), 0, SIZE_MAX, 9),
            common::WrenchTable::Upsert::kReplaced);
  EXPECT_EQ(t.active()[1].wrench.force[0], 30.0);
  EXPECT_EQ(t.expire(100), 2u);
  EXPECT_EQ(t.size(), 0u);
}

TEST(WrenchTable, FullTableRefusesNewKeysButAcceptsReplacements) {
  common::WrenchTable t(3);
  for (int k = 0; k < 3; ++k)
    EXPECT_EQ(t.upsert(wrench(1, 0, k, 1.0), 0, SIZE_MAX, 10),
              common::WrenchTable::Upsert::kInserted);
  EXPECT_EQ(t.upsert(wrench(1, 0, 3, 1.0), 0, SIZE_MAX, 10), common::WrenchTable::Upsert::kFull);
  EXPECT_EQ(t.size(), 3u);
  EXPECT_EQ(t.upsert(wrench(1, 0, 1, 5.0), 0, SIZE_MAX, 10),
            common::WrenchTable::Upsert::kReplaced);
  t.expire(10);
  EXPECT_EQ(t.upsert(wrench(1, 0, 3, 1.0), 0, SIZE_MAX, 20),
            common::WrenchTable::Upsert::kInserted);
}

TEST(WrenchTable, ChurnKeepsTheIndexConsistent) {
  // Many inserts, replacements and expiries: every live key is found exactly once.
  common::WrenchTable t(64);
  std::int64_t tick = 0;
  for (int round = 0; round < 2000; ++round) {
    const int key = (round * 7919) % 97;
    t.upsert(wrench(key % 5, key % 3, key, round), 0, SIZE_MAX, tick + 1 + round % 13);
    if (round % 3 == 0) t.expire(++tick);
    for (const common::ActiveWrench& e : t.active()) {
      int same = 0;
      for (const common::ActiveWrench& f : t.active())
        same += f.wrench.source == e.wrench.source && f.wrench.body == e.wrench.body &&
                f.wrench.key == e.wrench.key;
      ASSERT_EQ(same, 1);
    }
  }
  t.clear();
  EXPECT_EQ(t.size(), 0u);
  EXPECT_EQ(t.upsert(wrench(1, 0, 0, 1.0), 0, SIZE_MAX, 1), common::WrenchTable::Upsert::kInserted);
}

TEST(WrenchTable, EachSenderHoldsAtMostItsShareAndANewcomerAlwaysGetsIn) {
  common::WrenchTable t(8);
  // Sender 1 floods with distinct keys: it gets its share of 5, no more.
  int accepted = 0;
  for (int key = 0; key < 20; ++key) {
    const common::WrenchTable::Upsert u = t.upsert(wrench(1, 0, key, 1.0), 1, 5, 100);
    if (u == common::WrenchTable::Upsert::kInserted) ++accepted;
    if (key >= 5) {
      EXPECT_EQ(u, common::WrenchTable::Upsert::kOverShare);
    }
  }
  EXPECT_EQ(accepted, 5);
  EXPECT_EQ(t.held_by(1), 5u);
  // Replacing one of its own keys is always allowed.
  EXPECT_EQ(t.upsert(wrench(1, 0, 0, 2.0), 1, 5, 100), common::WrenchTable::Upsert::kReplaced);
  // Senders 2 and 3 fill the table (8 entries: 5 + 3).
  EXPECT_EQ(t.upsert(wrench(2, 0, 0, 1.0), 2, 5, 100), common::WrenchTable::Upsert::kInserted);
  EXPECT_EQ(t.upsert(wrench(2, 0, 1, 1.0), 2, 5, 100), common::WrenchTable::Upsert::kInserted);
  EXPECT_EQ(t.upsert(wrench(3, 0, 0, 1.0), 3, 5, 100), common::WrenchTable::Upsert::kInserted);
  EXPECT_EQ(t.size(), 8u);
  // A newcomer takes the oldest entry of the sender holding the most (1), not a refusal.
  EXPECT_EQ(t.upsert(wrench(4, 0, 0, 1.0), 4, 5, 100), common::WrenchTable::Upsert::kInserted);
  EXPECT_EQ(t.held_by(1), 4u);
  EXPECT_EQ(t.held_by(4), 1u);
  EXPECT_EQ(t.size(), 8u);
  // The evicted one was sender 1's oldest (key 0, replaced above but first in arrival order).
  bool key0 = false;
  for (const common::ActiveWrench& e : t.active())
    key0 = key0 || (e.sender == 1 && e.wrench.key == 0);
  EXPECT_FALSE(key0);
  // When every sender holds about as many, the table is full for real.
  common::WrenchTable even(2);
  EXPECT_EQ(even.upsert(wrench(1, 0, 0, 1.0), 1, 5, 100), common::WrenchTable::Upsert::kInserted);
  EXPECT_EQ(even.upsert(wrench(2, 0, 0, 1.0), 2, 5, 100), common::WrenchTable::Upsert::kInserted);
  EXPECT_EQ(even.upsert(wrench(3, 0, 0, 1.0), 3, 5, 100), common::WrenchTable::Upsert::kFull);
  // Expiry gives the share back.
  t.expire(100);
  EXPECT_EQ(t.size(), 0u);
  EXPECT_EQ(t.held_by(1), 0u);
}

TEST(WrenchTable, OwnersNeverReplaceEachOthersWrenches) {
  common::WrenchTable t(4);
  Wrench a = wrench(1, 0, 0, 1.0);
  a.owner = 11;
  Wrench b = a;
  b.owner = 22;  // another identity writing the same source, body and key
  EXPECT_EQ(t.upsert(a, 11, 5, 100), common::WrenchTable::Upsert::kInserted);
  EXPECT_EQ(t.upsert(b, 22, 5, 100), common::WrenchTable::Upsert::kInserted);
  EXPECT_EQ(t.size(), 2u);
}

}  // namespace
}  // namespace rigid::loop
