// Publisher: states handed over by swapping buffers (Publisher::hand_over) reach the bus whole and
// in order, interleaved with copied offers, while the loop keeps refilling the frame it got back;
// and, as rigidd runs them, two publishers reading the same shared slots (one bus slow, one fast)
// each send whole states in order, the last one included, and let go of every slot.
#include "loop/publisher.hpp"

#include <gtest/gtest.h>
#include <pthread.h>
#include <sched.h>

#include <atomic>
#include <chrono>
#include <ctime>
#include <mutex>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "loop/log.hpp"
#include "loop_harness.hpp"

namespace rigid::loop {
namespace {

// Keeps every state it is given.
class RecordingTransport final : public transport::NullTransport {
 public:
  using NullTransport::publish;
  transport::PublishResult publish(const rigid::StateFrame& s) override {
    {
      const std::lock_guard lock(mutex);
      states.push_back(s);
    }
    // A slow bus: the loop offers newer states meanwhile, and must not touch this one's slot.
    if (delay_us > 0) {
      std::this_thread::sleep_for(std::chrono::microseconds(delay_us));
      if (s.tick != states.back().tick || s.position != states.back().position) ++changed;
    }
    return ok();
  }

  int delay_us = 0;
  int changed = 0;  // states whose frame changed while being sent
  std::mutex mutex;
  std::vector<rigid::StateFrame> states;
};

class NullLog final : public Log {
 public:
  void line(std::string_view) override {}
};

constexpr int kFrameBodies = 5;

// Every value of the state of tick t is a function of t and its place: a state mixed from two
// ticks, or a stale value left in a swapped buffer, shows.
double value(std::int64_t tick, int array, std::size_t k) {
  return static_cast<double>(tick) * 1000.0 + array * 100.0 + static_cast<double>(k);
}

void fill(std::int64_t tick, rigid::StateFrame& f) {
  f.tick = tick;
  f.sim_time = static_cast<double>(tick) * 1e-3;
  std::vector<double>* arrays[] = {&f.position, &f.orientation, &f.linear_velocity,
                                   &f.angular_velocity};
  for (int a = 0; a < 4; ++a)
    for (std::size_t k = 0; k < arrays[a]->size(); ++k)
      (*arrays[a])[k] = value(tick, a, k);
}

// Every state `bus` got is whole (each value its tick's), in increasing tick order, the last
// being `last_tick`.
void expect_whole_and_in_order(RecordingTransport& bus, const rigid::StateFrame& shape,
                               std::int64_t last_tick) {
  const std::lock_guard lock(bus.mutex);
  ASSERT_FALSE(bus.states.empty());
  EXPECT_EQ(bus.states.back().tick, last_tick) << "the last state is never skipped";
  std::int64_t previous = 0;
  for (const rigid::StateFrame& s : bus.states) {
    EXPECT_GT(s.tick, previous) << "states out of order or sent twice";
    previous = s.tick;
    ASSERT_EQ(s.ids, shape.ids);
    ASSERT_TRUE(s.lengths_agree());
    const std::vector<double>* arrays[] = {&s.position, &s.orientation, &s.linear_velocity,
                                           &s.angular_velocity};
    for (int a = 0; a < 4; ++a)
      for (std::size_t k = 0; k < arrays[a]->size(); ++k)
        ASSERT_EQ((*arrays[a])[k], value(s.tick, a, k))
            << "tick " << s.tick << " array " << a << " element " << k;
  }
}

rigid::StateFrame make_shape() {
  rigid::StateFrame shape;
  shape.resize(kFrameBodies);
  for (int i = 0; i < kFrameBodies; ++i)
    shape.ids[static_cast<std::size_t>(i)] = 10 + i;
  return shape;
}

TEST(Publisher, HandedOverStatesArriveWholeAndInOrder) {
  const rigid::StateFrame shape = make_shape();
  RecordingTransport bus;
  NullLog log;
  Publisher publisher(bus, shape, log);
  publisher.start();
  rigid::StateFrame frame = shape;
  constexpr std::int64_t kTicks = 3000;
  for (std::int64_t t = 1; t <= kTicks; ++t) {
    fill(t, frame);
    if (t % 3 == 0) {
      publisher.offer(frame);
    } else {
      publisher.hand_over(frame);
    }
    // What comes back has the shape the loop needs for its next fill, without allocating.
    ASSERT_TRUE(frame.lengths_agree());
    ASSERT_EQ(frame.ids, shape.ids);
  }
  publisher.stop();  // sends what is pending

  EXPECT_EQ(static_cast<std::int64_t>(bus.states.size()), publisher.states_sent());  // joined
  expect_whole_and_in_order(bus, shape, kTicks);
}

TEST(Publisher, TwoBusesShareEachStateAndLetGoOfEverySlot) {
  const rigid::StateFrame shape = make_shape();
  SharedStates states(shape);
  RecordingTransport slow, fast;
  slow.delay_us = 200;
  NullLog log;
  Publisher a(slow, states, log);
  Publisher b(fast, states, log);
  ASSERT_EQ(states.slots(), 5);
  a.start();
  b.start();
  rigid::StateFrame frame = shape;
  constexpr std::int64_t kTicks = 3000;
  for (std::int64_t t = 1; t <= kTicks; ++t) {
    fill(t, frame);
    // As the server: swapped into a free slot (copied every 4th), offered to both.
    const int slot = t % 4 == 0 ? states.put_copied(frame, 2) : states.put_swapped(frame, 2);
    a.offer_slot(slot);
    b.offer_slot(slot);
    ASSERT_TRUE(frame.lengths_agree());
    ASSERT_EQ(frame.ids, shape.ids);
    if (t % 500 == 0) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  a.stop();
  b.stop();

  expect_whole_and_in_order(slow, shape, kTicks);
  expect_whole_and_in_order(fast, shape, kTicks);
  EXPECT_EQ(a.states_sent() + a.states_skipped(), kTicks);
  EXPECT_EQ(b.states_sent() + b.states_skipped(), kTicks);
  EXPECT_GT(a.states_skipped(), 0) << "the slow bus should have had states replaced";
  EXPECT_EQ(slow.changed, 0) << "a slot was refilled while a bus was sending it";
  for (int k = 0; k < states.slots(); ++k)
    EXPECT_EQ(states.holders(k), 0) << "slot " << k << " still held after both stopped";
  // The same state carries the same stamp on both buses (stamped once, when put).
  const std::lock_guard la(slow.mutex);
  const std::lock_guard lb(fast.mutex);
  EXPECT_EQ(slow.states.back().stamp_ns, fast.states.back().stamp_ns);
  EXPECT_NE(slow.states.back().stamp_ns, 0);
}

// A transport that spends `busy_us` of CPU time on each state (a large world's encoding).
class BusyTransport final : public transport::NullTransport {
 public:
  using NullTransport::publish;
  transport::PublishResult publish(const rigid::StateFrame&) override {
    timespec t0{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t0);
    for (;;) {
      timespec t{};
      clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
      const long us = (t.tv_sec - t0.tv_sec) * 1'000'000L + (t.tv_nsec - t0.tv_nsec) / 1000;
      if (us >= busy_us.load()) break;
    }
    return ok();
  }
  std::atomic<long> busy_us{0};
};

class LinesLog final : public Log {
 public:
  void line(std::string_view text) override {
    const std::lock_guard lock(mutex);
    lines.emplace_back(text);
  }
  std::vector<std::string> taken() {
    const std::lock_guard lock(mutex);
    return lines;
  }
  std::mutex mutex;
  std::vector<std::string> lines;
};

// A publisher at real-time priority that takes most of a CPU (states that cost 4 ms each, offered
// every 2 ms) steps down to normal priority within its first window or two and says so; once its
// states are cheap again it steps back up (or says why it could not: without the privilege).
TEST(Publisher, StepsDownFromRealTimeWhileItTakesMoreThanItsShareOfACpu) {
  const rigid::StateFrame shape = make_shape();
  BusyTransport bus;
  LinesLog log;
  Publisher publisher(bus, shape, log);
  publisher.start();
  constexpr int kPriority = 1;
  sched_param param{};
  param.sched_priority = kPriority;
  const bool privileged = pthread_setschedparam(publisher.native_handle(), SCHED_FIFO, &param) == 0;
  publisher.watch_realtime_share(kPriority);
  const auto policy = [&] {
    int p = -1;
    sched_param sp{};
    EXPECT_EQ(pthread_getschedparam(publisher.native_handle(), &p, &sp), 0);
    return p;
  };
  const auto offer_until = [&](auto done, std::chrono::milliseconds every) {
    rigid::StateFrame frame = shape;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
    for (std::int64_t t = 1; !done() && std::chrono::steady_clock::now() < deadline; ++t) {
      fill(t, frame);
      publisher.offer(frame);
      std::this_thread::sleep_for(every);
    }
  };
  bus.busy_us = 4000;
  offer_until([&] { return publisher.priority_step_downs() > 0; }, std::chrono::milliseconds(2));
  ASSERT_EQ(publisher.priority_step_downs(), 1);
  EXPECT_EQ(policy(), SCHED_OTHER);
  bus.busy_us = 0;
  offer_until([&] { return log.taken().size() >= 2; }, std::chrono::milliseconds(20));
  const int policy_after = policy();
  publisher.stop();
  const std::vector<std::string> lines = log.taken();
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0].rfind("publisher dds: took ", 0), 0u) << lines[0];
  EXPECT_NE(lines[0].find("of a CPU over the last second at real-time priority, more than 25%: "
                          "at normal priority until it takes less than 10%"),
            std::string::npos)
      << lines[0];
  if (privileged) {
    EXPECT_NE(lines[1].find(": back at SCHED_FIFO priority 1"), std::string::npos) << lines[1];
    EXPECT_EQ(policy_after, SCHED_FIFO);
  } else {
    EXPECT_NE(lines[1].find("but could not change its priority"), std::string::npos) << lines[1];
    EXPECT_EQ(policy_after, SCHED_OTHER);
  }
  EXPECT_EQ(publisher.priority_step_downs(), 1);
}

}  // namespace
}  // namespace rigid::loop
