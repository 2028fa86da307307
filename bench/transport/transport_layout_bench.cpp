// Which layout should rigid/state have on DDS? The same world state serialized and deserialized by
// Cyclone's CDR stream code as
//   flat:    msgs/rigid.idl's WorldState, per-body values in flat sequences of doubles;
//   structs: bench/transport/transport_layout_bench.idl, a sequence of one struct per body.
// Write = what dds_write spends turning the sample into bytes; read = what a reader spends checking
// (normalize) and deserializing them. The stream buffer and the decoded sample are reused, as in
// steady state, so allocation is not measured. The LCM rows give the other bus's cost for the same
// state through rigid's own codec (conversion included), for scale.
//
// Run (from the build directory; medians of 5 runs):
//   bench/transport_layout_bench --benchmark_repetitions=5
//       --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>
#include <dds/dds.h>
#include <dds/ddsi/ddsi_cdrstream.h>
#include <rigid.h>
#include <transport_layout_bench.h>

#include <cstdint>
#include <cstring>
#include <random>
#include <span>
#include <vector>

#include "rigid/messages.hpp"
#include "transport/dds/dds_cdr_codec.hpp"
#include "transport/lcm/lcm_codec.hpp"

namespace {

using rigid::StateFrame;

StateFrame random_state(std::size_t bodies) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> value(-10.0, 10.0);
  StateFrame state;
  state.tick = 123456;
  state.sim_time = 123.456;
  state.stamp_ns = 1700000000000000000;
  state.resize(bodies);
  for (std::size_t i = 0; i < bodies; ++i)
    state.ids[i] = static_cast<std::int32_t>(i);
  for (double& x : state.position)
    x = value(rng);
  for (double& x : state.orientation)
    x = value(rng);
  for (double& x : state.linear_velocity)
    x = value(rng);
  for (double& x : state.angular_velocity)
    x = value(rng);
  return state;
}

// The flat sample borrows the state's vectors, as the DDS transport does.
template <class Seq, class T>
void lend(std::vector<T>& in, Seq& out) {
  out._maximum = out._length = static_cast<std::uint32_t>(in.size());
  out._buffer = in.data();
  out._release = false;
}

struct FlatLayout {
  using Sample = rigid_WorldState;
  static const dds_topic_descriptor_t& descriptor() { return rigid_WorldState_desc; }

  explicit FlatLayout(StateFrame& state) {
    sample.tick = state.tick;
    sample.sim_time = state.sim_time;
    sample.stamp_ns = state.stamp_ns;
    lend(state.ids, sample.ids);
    lend(state.position, sample.position);
    lend(state.orientation, sample.orientation);
    lend(state.linear_velocity, sample.linear_velocity);
    lend(state.angular_velocity, sample.angular_velocity);
  }
  Sample sample{};
};

struct StructsLayout {
  using Sample = rigid_bench_WorldStateOfStructs;
  static const dds_topic_descriptor_t& descriptor() { return rigid_bench_WorldStateOfStructs_desc; }

  explicit StructsLayout(StateFrame& state) : bodies(state.body_count()) {
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      rigid_bench_BodyState& body = bodies[i];
      body.id = state.ids[i];
      std::memcpy(body.position, &state.position[3 * i], sizeof body.position);
      std::memcpy(body.orientation, &state.orientation[4 * i], sizeof body.orientation);
      std::memcpy(body.linear_velocity, &state.linear_velocity[3 * i], sizeof body.linear_velocity);
      std::memcpy(body.angular_velocity, &state.angular_velocity[3 * i],
                  sizeof body.angular_velocity);
    }
    sample.tick = state.tick;
    sample.sim_time = state.sim_time;
    sample.stamp_ns = state.stamp_ns;
    lend(bodies, sample.bodies);
  }
  std::vector<rigid_bench_BodyState> bodies;
  Sample sample{};
};

// RAII around the CDR output stream.
class OutStream {
 public:
  explicit OutStream(std::uint32_t xcdr_version) { dds_ostream_init(&stream_, 0, xcdr_version); }
  ~OutStream() { dds_ostream_fini(&stream_); }
  OutStream(const OutStream&) = delete;
  OutStream& operator=(const OutStream&) = delete;
  dds_ostream_t* get() { return &stream_; }

 private:
  dds_ostream_t stream_{};
};

template <class Layout>
void BM_DdsWrite(benchmark::State& bench) {
  StateFrame state = random_state(static_cast<std::size_t>(bench.range(0)));
  Layout layout(state);
  const std::uint32_t* ops = Layout::descriptor().m_ops;
  OutStream out(dds_stream_minimum_xcdr_version(ops));
  for (auto _ : bench) {
    out.get()->m_index = 0;
    dds_stream_write(out.get(), reinterpret_cast<const char*>(&layout.sample), ops);
    benchmark::DoNotOptimize(out.get()->m_buffer);
    benchmark::ClobberMemory();
  }
  bench.SetBytesProcessed(static_cast<std::int64_t>(bench.iterations()) * out.get()->m_index);
  bench.counters["bytes"] = out.get()->m_index;
}

template <class Layout>
void BM_DdsRead(benchmark::State& bench) {
  StateFrame state = random_state(static_cast<std::size_t>(bench.range(0)));
  Layout layout(state);
  const std::uint32_t* ops = Layout::descriptor().m_ops;
  const std::uint32_t xcdr = dds_stream_minimum_xcdr_version(ops);
  OutStream out(xcdr);
  dds_stream_write(out.get(), reinterpret_cast<const char*>(&layout.sample), ops);
  const std::uint32_t size = out.get()->m_index;
  std::vector<unsigned char> bytes(out.get()->m_buffer, out.get()->m_buffer + size);

  typename Layout::Sample decoded{};
  for (auto _ : bench) {
    std::uint32_t end = 0;
    if (dds_stream_normalize_data(reinterpret_cast<char*>(bytes.data()), &end, size, false, xcdr,
                                  ops) == nullptr) {
      bench.SkipWithError("normalize rejected the bytes");
      break;
    }
    dds_istream_t in;
    dds_istream_init(&in, size, bytes.data(), xcdr);
    dds_stream_read(&in, reinterpret_cast<char*>(&decoded), ops);
    dds_istream_fini(&in);
    benchmark::DoNotOptimize(decoded);
    benchmark::ClobberMemory();
  }
  dds_stream_free_sample(&decoded, ops);
  bench.SetBytesProcessed(static_cast<std::int64_t>(bench.iterations()) * size);
}

// rigid's public codecs: conversion from/to StateFrame included.
template <class Codec>
void BM_CodecEncode(benchmark::State& bench) {
  const StateFrame state = random_state(static_cast<std::size_t>(bench.range(0)));
  Codec codec;
  std::size_t size = 0;
  for (auto _ : bench) {
    const std::span<const std::uint8_t> bytes = codec.encode(state);
    size = bytes.size();
    benchmark::DoNotOptimize(bytes.data());
  }
  bench.SetBytesProcessed(static_cast<std::int64_t>(bench.iterations() * size));
}

template <class Codec>
void BM_CodecDecode(benchmark::State& bench) {
  const StateFrame state = random_state(static_cast<std::size_t>(bench.range(0)));
  Codec codec;
  const std::span<const std::uint8_t> encoded = codec.encode(state);
  const std::vector<std::uint8_t> bytes(encoded.begin(), encoded.end());
  StateFrame decoded;
  for (auto _ : bench) {
    if (codec.decode(bytes, decoded) != rigid::transport::DecodeStatus::kOk) {
      bench.SkipWithError("decode failed");
      break;
    }
    benchmark::DoNotOptimize(decoded.position.data());
  }
  bench.SetBytesProcessed(static_cast<std::int64_t>(bench.iterations() * bytes.size()));
}

using rigid::transport::dds::CdrCodec;
using LcmCodec = rigid::transport::lcm::Codec;

BENCHMARK(BM_DdsWrite<FlatLayout>)->Arg(100)->Arg(1000)->Arg(10000);
BENCHMARK(BM_DdsWrite<StructsLayout>)->Arg(100)->Arg(1000)->Arg(10000);
BENCHMARK(BM_DdsRead<FlatLayout>)->Arg(100)->Arg(1000)->Arg(10000);
BENCHMARK(BM_DdsRead<StructsLayout>)->Arg(100)->Arg(1000)->Arg(10000);
BENCHMARK(BM_CodecEncode<CdrCodec>)->Arg(1000)->Arg(100000);
BENCHMARK(BM_CodecDecode<CdrCodec>)->Arg(1000);
BENCHMARK(BM_CodecEncode<LcmCodec>)->Arg(1000)->Arg(100000);
BENCHMARK(BM_CodecDecode<LcmCodec>)->Arg(1000);

}  // namespace

BENCHMARK_MAIN();
