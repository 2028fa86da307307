// What handing a state to two buses costs rigidd's loop thread, per state, by number of bodies:
// the way it was (the state copied into the first bus's triple buffer and swapped into the
// last's: Publisher::offer then Publisher::hand_over, each publisher with its own buffers), and
// the shared way (swapped once into a slot both publishers read: SharedStates::put_swapped, then
// Publisher::offer_slot to each; rigidd's loop now writes the state into such a slot in place,
// SharedStates::lend, which leaves the same hand-over without the swap). The publishers run, on a
// bus that sends nothing, so slots are taken and let go as in rigidd.
//
//   build/bench/fanout_bench [--benchmark_repetitions=5 --benchmark_report_aggregates_only=true]
#include <benchmark/benchmark.h>

#include <string_view>

#include "loop/log.hpp"
#include "loop/publisher.hpp"
#include "loop/shared_states.hpp"
#include "transport/null_transport.hpp"

namespace {

using rigid::loop::Publisher;
using rigid::loop::SharedStates;

class NullLog final : public rigid::loop::Log {
 public:
  void line(std::string_view) override {}
};

rigid::StateFrame shaped(std::int64_t bodies) {
  rigid::StateFrame f;
  f.resize(static_cast<std::size_t>(bodies));
  for (std::size_t i = 0; i < f.ids.size(); ++i) {
    f.ids[i] = static_cast<std::int32_t>(i);
    f.position[3 * i] = static_cast<double>(i);
  }
  return f;
}

void set_bytes(benchmark::State& state, std::int64_t bodies) {
  state.SetItemsProcessed(state.iterations());  // states handed over
  state.counters["MB_per_state"] =
      static_cast<double>(bodies) * (4 + 13 * 8) / 1e6;  // id, pose and velocities
}

// Before: a copy into the first bus's buffer, a swap into the last's.
void BM_CopyToFirstSwapIntoLast(benchmark::State& state) {
  const std::int64_t n = state.range(0);
  const rigid::StateFrame shape = shaped(n);
  rigid::transport::NullTransport bus_a, bus_b;
  NullLog log;
  Publisher a(bus_a, shape, log);
  Publisher b(bus_b, shape, log);
  a.start();
  b.start();
  rigid::StateFrame frame = shape;
  for (auto _ : state) {
    frame.tick += 1;
    a.offer(frame);
    b.hand_over(frame);
    benchmark::ClobberMemory();
  }
  a.stop();
  b.stop();
  set_bytes(state, n);
}

// Now: one swap into a slot both buses read.
void BM_SwapIntoSharedSlot(benchmark::State& state) {
  const std::int64_t n = state.range(0);
  const rigid::StateFrame shape = shaped(n);
  SharedStates states(shape);
  rigid::transport::NullTransport bus_a, bus_b;
  NullLog log;
  Publisher a(bus_a, states, log);
  Publisher b(bus_b, states, log);
  a.start();
  b.start();
  rigid::StateFrame frame = shape;
  for (auto _ : state) {
    frame.tick += 1;
    const int slot = states.put_swapped(frame, 2);
    a.offer_slot(slot);
    b.offer_slot(slot);
    benchmark::ClobberMemory();
  }
  a.stop();
  b.stop();
  set_bytes(state, n);
}

BENCHMARK(BM_CopyToFirstSwapIntoLast)->Arg(1000)->Arg(10000)->Arg(100000)->UseRealTime();
BENCHMARK(BM_SwapIntoSharedSlot)->Arg(1000)->Arg(10000)->Arg(100000)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
