// SharedStates: the slots the loop puts states in for every bus's publisher. 2 R + 1 slots for R
// readers; the writer always finds a free one while each reader holds at most two; a slot is free
// again once every holder released it; frames go in whole (swapped or copied) and come back with
// their shape; sharing with more readers than were added is refused.
#include "loop/shared_states.hpp"

#include <gtest/gtest.h>

#include <set>
#include <stdexcept>

namespace rigid::loop {
namespace {

rigid::StateFrame shaped(int bodies) {
  rigid::StateFrame f;
  f.resize(static_cast<std::size_t>(bodies));
  for (int i = 0; i < bodies; ++i)
    f.ids[static_cast<std::size_t>(i)] = 7 + i;
  return f;
}

TEST(SharedStates, TwoSlotsAReaderAndOneForTheWriter) {
  SharedStates s(shaped(3));
  EXPECT_EQ(s.slots(), 1);
  EXPECT_EQ(s.add_reader(), 0);
  EXPECT_EQ(s.add_reader(), 1);
  EXPECT_EQ(s.readers(), 2);
  EXPECT_EQ(s.slots(), 5);
}

TEST(SharedStates, SwappedFramesGoInWholeAndComeBackShaped) {
  SharedStates s(shaped(3));
  (void)s.add_reader();
  (void)s.add_reader();
  rigid::StateFrame f = shaped(3);
  f.tick = 42;
  f.position = {1, 2, 3, 4, 5, 6, 7, 8, 9};
  const int slot = s.put_swapped(f, 2);
  EXPECT_EQ(s.frame(slot).tick, 42);
  EXPECT_EQ(s.frame(slot).position[8], 9.0);
  EXPECT_NE(s.frame(slot).stamp_ns, 0) << "stamped when put";
  EXPECT_EQ(s.holders(slot), 2);
  // What the writer gets back is another slot's frame: the same shape, ready to refill.
  EXPECT_TRUE(f.lengths_agree());
  EXPECT_EQ(f.ids, shaped(3).ids);

  f.tick = 43;
  const int copied = s.put_copied(f, 1);
  EXPECT_NE(copied, slot) << "a held slot was reused";
  EXPECT_EQ(s.frame(copied).tick, 43);
  EXPECT_EQ(f.tick, 43) << "a copy leaves the frame as it was";
}

// The loop's way in rigidd: a free slot's frame filled in place, then shared; no frame of its own.
TEST(SharedStates, LentFramesAreFilledInPlaceAndShared) {
  SharedStates s(shaped(3));
  (void)s.add_reader();
  (void)s.add_reader();
  EXPECT_THROW((void)s.put_lent(2), std::logic_error) << "nothing lent";
  rigid::StateFrame& f = s.lend();
  EXPECT_EQ(f.ids, shaped(3).ids) << "a lent frame has the slots' shape";
  EXPECT_EQ(&s.lend(), &f) << "lent again before put_lent: the same slot";
  f.tick = 42;
  f.position[8] = 9;
  EXPECT_THROW((void)s.put_lent(3), std::logic_error) << "more holders than readers";
  const int slot = s.put_lent(2);
  EXPECT_EQ(&s.frame(slot), &f) << "shared where it was written: no copy";
  EXPECT_EQ(s.frame(slot).tick, 42);
  EXPECT_EQ(s.frame(slot).position[8], 9.0);
  EXPECT_NE(s.frame(slot).stamp_ns, 0) << "stamped when put";
  EXPECT_EQ(s.holders(slot), 2);
  // The next lend is another slot while this one is held, and the lent slot is never given to a
  // put_swapped / put_copied meanwhile.
  rigid::StateFrame& g = s.lend();
  EXPECT_NE(&g, &f);
  rigid::StateFrame other = shaped(3);
  for (int k = 0; k < 3; ++k) {
    const int put = s.put_copied(other, 1);
    EXPECT_NE(&s.frame(put), &g) << "a put took the lent slot";
  }
  EXPECT_THROW((void)s.put_copied(other, 1), std::logic_error)
      << "all five slots held or lent: the lent one is not free";
}

TEST(SharedStates, TheWriterFindsAFreeSlotWhileEachReaderHoldsTwo) {
  constexpr int kReaders = 3;
  SharedStates s(shaped(2));
  for (int r = 0; r < kReaders; ++r)
    (void)s.add_reader();
  rigid::StateFrame f = shaped(2);
  // Each reader holds two different slots (one offered, one being sent): 2 R slots held.
  std::set<int> held;
  for (int r = 0; r < kReaders; ++r) {
    held.insert(s.put_swapped(f, 1));
    held.insert(s.put_swapped(f, 1));
  }
  ASSERT_EQ(static_cast<int>(held.size()), 2 * kReaders) << "a held slot was handed out again";
  const int last = s.put_swapped(f, 1);
  EXPECT_EQ(held.count(last), 0u);
  // Now every slot is held: the invariant broken (a reader with three), the writer says so.
  EXPECT_THROW((void)s.put_swapped(f, 1), std::logic_error);
  // A slot is free again once all its holders let go, not before.
  const int shared = *held.begin();
  s.release(shared);
  EXPECT_EQ(s.holders(shared), 0);
  EXPECT_EQ(s.put_copied(f, kReaders), shared);
  for (int k = 0; k < kReaders - 1; ++k)
    s.release(shared);
  EXPECT_EQ(s.holders(shared), 1);
  EXPECT_THROW((void)s.put_copied(f, 1), std::logic_error);
  s.release(shared);
  EXPECT_EQ(s.put_copied(f, 1), shared);
}

TEST(SharedStates, SharingWithMoreReadersThanAddedIsRefused) {
  SharedStates s(shaped(1));
  (void)s.add_reader();
  rigid::StateFrame f = shaped(1);
  f.tick = 5;
  EXPECT_THROW((void)s.put_swapped(f, 2), std::logic_error);
  EXPECT_THROW((void)s.put_copied(f, 0), std::logic_error);
  EXPECT_EQ(s.holders(0) + s.holders(1) + s.holders(2), 0) << "a refused put holds nothing";
  EXPECT_EQ(f.tick, 5) << "a refused put left the frame alone";
}

TEST(SharedStates, ArrivalsAreKeptPerReader) {
  SharedStates s(shaped(1));
  (void)s.add_reader();
  (void)s.add_reader();
  rigid::StateFrame f = shaped(1);
  const int slot = s.put_swapped(f, 2);
  s.set_arrival(slot, 0, 100);
  s.set_arrival(slot, 1, 200);
  EXPECT_EQ(s.arrival(slot, 0), 100);
  EXPECT_EQ(s.arrival(slot, 1), 200);
}

}  // namespace
}  // namespace rigid::loop
