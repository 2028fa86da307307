// The command queue: bounded, FIFO, never blocks, safe with several producers; drops are the
// caller's to count (the intake counts them as queue_full, tested in intake_test).
#include "loop/bounded_queue.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <thread>
#include <vector>

namespace rigid::loop {
namespace {

TEST(BoundedQueue, FifoAndBounded) {
  BoundedQueue<int> q(4);
  EXPECT_EQ(q.capacity(), 4u);
  for (int i = 0; i < 4; ++i)
    EXPECT_TRUE(q.try_push(i));
  EXPECT_FALSE(q.try_push(99));  // full: refused at once
  int v = -1;
  for (int i = 0; i < 4; ++i) {
    ASSERT_TRUE(q.try_pop(v));
    EXPECT_EQ(v, i);
  }
  EXPECT_FALSE(q.try_pop(v));
  EXPECT_TRUE(q.try_push(5));  // wraps around
  ASSERT_TRUE(q.try_pop(v));
  EXPECT_EQ(v, 5);
}

TEST(BoundedQueue, CapacityIsRoundedUpToAPowerOfTwo) {
  EXPECT_EQ(BoundedQueue<int>(1000).capacity(), 1024u);
  EXPECT_EQ(BoundedQueue<int>(0).capacity(), 2u);
}

TEST(BoundedQueue, ConcurrentProducersLoseNothingAccepted) {
  BoundedQueue<std::int64_t> q(64);
  constexpr int kProducers = 3;
  constexpr std::int64_t kEach = 20000;
  std::atomic<std::int64_t> accepted{0}, dropped{0};
  std::atomic<bool> done{false};
  std::vector<std::thread> producers;
  for (int p = 0; p < kProducers; ++p) {
    producers.emplace_back([&, p] {
      for (std::int64_t i = 0; i < kEach; ++i) {
        if (q.try_push(p * kEach + i)) {
          accepted.fetch_add(1);
        } else {
          dropped.fetch_add(1);
        }
      }
    });
  }
  std::int64_t popped = 0;
  std::vector<std::int64_t> last(kProducers, -1);
  std::thread consumer([&] {
    std::int64_t v = 0;
    for (;;) {
      if (q.try_pop(v)) {
        ++popped;
        const auto p = static_cast<std::size_t>(v / kEach);
        EXPECT_GT(v, last[p]);  // each producer's values come out in order
        last[p] = v;
      } else if (done.load()) {
        if (!q.try_pop(v)) break;
        ++popped;
      }
    }
  });
  for (auto& t : producers)
    t.join();
  done.store(true);
  consumer.join();
  EXPECT_EQ(accepted.load() + dropped.load(), kProducers * kEach);
  EXPECT_EQ(popped, accepted.load());
}

}  // namespace
}  // namespace rigid::loop
