// Publisher: states handed over by swapping buffers (Publisher::hand_over, what rigidd's loop does
// for its last bus) reach the bus whole and in order, interleaved with copied offers, while the
// loop keeps refilling the frame it got back.
#include "loop/publisher.hpp"

#include <gtest/gtest.h>

#include <mutex>
#include <string_view>
#include <vector>

#include "loop/log.hpp"
#include "loop_harness.hpp"

namespace rigid::loop {
namespace {

// Keeps every state it is given.
class RecordingTransport final : public testing::NullTransport {
 public:
  using NullTransport::publish;
  transport::PublishResult publish(const rigid::StateFrame& s) override {
    const std::lock_guard lock(mutex);
    states.push_back(s);
    return ok();
  }

  std::mutex mutex;
  std::vector<rigid::StateFrame> states;
};

class NullLog final : public Log {
 public:
  void line(std::string_view) override {}
};

constexpr int kBodies = 5;

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

TEST(Publisher, HandedOverStatesArriveWholeAndInOrder) {
  rigid::StateFrame shape;
  shape.resize(kBodies);
  for (int i = 0; i < kBodies; ++i)
    shape.ids[static_cast<std::size_t>(i)] = 10 + i;
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

  const std::lock_guard lock(bus.mutex);
  ASSERT_FALSE(bus.states.empty());
  EXPECT_EQ(bus.states.back().tick, kTicks) << "the last state is never skipped";
  EXPECT_EQ(static_cast<std::int64_t>(bus.states.size()), publisher.states_sent());
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

}  // namespace
}  // namespace rigid::loop
