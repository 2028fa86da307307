// The queue of contact events between the loop and one publisher: ticks come out whole and in
// order, across the end of its storage; a tick without room is refused and nothing of it queued;
// and a producer and a consumer on two threads lose and reorder nothing.
#include "loop/contact_outbox.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <thread>

namespace rigid::loop {
namespace {

rigid::ContactEvents tick_of(std::int64_t tick, std::size_t events) {
  rigid::ContactEvents c;
  c.tick = tick;
  c.sim_time = static_cast<double>(tick) * 1e-3;
  c.dropped = tick / 3;
  c.resize(events);
  for (std::size_t i = 0; i < events; ++i) {
    const double v = static_cast<double>(tick) + static_cast<double>(i) / 8.0;
    c.kinds[i] = static_cast<rigid::ContactKind>(1 + (tick + static_cast<std::int64_t>(i)) % 5);
    c.bodies[i] = static_cast<std::int32_t>(tick);
    c.parts[i] = static_cast<std::int32_t>(i);
    c.times[i] = v;
    for (std::size_t k = 0; k < 3; ++k) {
      c.position[3 * i + k] = v + static_cast<double>(k);
      c.normal[3 * i + k] = -v - static_cast<double>(k);
      c.impulse[3 * i + k] = v * static_cast<double>(k);
    }
  }
  return c;
}

TEST(ContactOutbox, TicksComeOutWholeAndInOrderAcrossTheEndOfItsStorage) {
  ContactOutbox box(4, 10);
  rigid::ContactEvents out;
  for (std::int64_t t = 1; t <= 40; ++t) {
    const rigid::ContactEvents in = tick_of(t, static_cast<std::size_t>(1 + t % 4));
    ASSERT_TRUE(box.put(in, 1000 + t)) << t;
    ASSERT_TRUE(box.take(out)) << t;
    EXPECT_EQ(out.stamp_ns, 1000 + t);
    out.stamp_ns = 0;
    EXPECT_EQ(out, in) << t;
  }
  EXPECT_FALSE(box.take(out));
}

TEST(ContactOutbox, ATickWithoutRoomIsRefusedWhole) {
  ContactOutbox box(3, 10);
  EXPECT_TRUE(box.put(tick_of(1, 4), 0));
  EXPECT_TRUE(box.put(tick_of(2, 4), 0));
  EXPECT_FALSE(box.has_room(3));
  EXPECT_FALSE(box.put(tick_of(3, 3), 0));   // 11 events > 10
  EXPECT_TRUE(box.put(tick_of(4, 2), 0));    // exactly full
  EXPECT_FALSE(box.put(tick_of(5, 0), 0));   // no tick left (3 queued)
  EXPECT_FALSE(box.put(tick_of(6, 11), 0));  // more than it could ever hold
  rigid::ContactEvents out;
  for (const std::int64_t t : {1, 2, 4}) {
    ASSERT_TRUE(box.take(out));
    EXPECT_EQ(out.tick, t);
  }
  EXPECT_FALSE(box.take(out));
  rigid::ContactEvents bad = tick_of(7, 2);
  bad.normal.pop_back();
  EXPECT_FALSE(box.put(bad, 0));
  EXPECT_TRUE(box.put(tick_of(8, 10), 0));
  ASSERT_TRUE(box.take(out));
  EXPECT_EQ(out, tick_of(8, 10));
}

TEST(ContactOutbox, AProducerAndAConsumerOnTwoThreadsLoseAndReorderNothing) {
  ContactOutbox box(8, 64);
  constexpr std::int64_t kTicks = 20000;
  std::atomic<bool> give_up{false};
  std::thread producer([&] {
    for (std::int64_t t = 1; t <= kTicks && !give_up.load();) {
      if (box.put(tick_of(t, static_cast<std::size_t>(t % 13)), t)) {
        ++t;
      } else {
        std::this_thread::yield();
      }
    }
  });
  rigid::ContactEvents out;
  std::int64_t expected = 1;
  std::int64_t first_wrong = 0;
  while (expected <= kTicks && first_wrong == 0) {
    if (!box.take(out)) {
      std::this_thread::yield();
      continue;
    }
    out.stamp_ns = 0;
    if (out != tick_of(expected, static_cast<std::size_t>(expected % 13))) first_wrong = expected;
    ++expected;
  }
  give_up = true;
  producer.join();
  EXPECT_EQ(first_wrong, 0) << "tick " << first_wrong << " came out wrong";
  EXPECT_FALSE(box.take(out));
}

}  // namespace
}  // namespace rigid::loop
