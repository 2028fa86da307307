// Bad payloads give a typed DecodeStatus, never a crash, an exception or a huge allocation:
// garbage, truncation, wrong fingerprints, forged counts and string lengths (LCM), and random
// corruption of valid payloads on both codecs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "random_messages.hpp"
#include "transport/dds/dds_cdr_codec.hpp"
#include "transport/lcm/lcm_codec.hpp"

namespace rigid::transport {
namespace {

using Bytes = std::vector<std::uint8_t>;
using testing::RandomMessages;

template <class Codec, class Message>
Bytes encode(Codec& codec, const Message& message) {
  const auto encoded = codec.encode(message);
  return Bytes(encoded.begin(), encoded.end());
}

// LCM integers are big-endian.
void put_be32(Bytes& bytes, std::size_t offset, std::uint32_t value) {
  for (int i = 0; i < 4; ++i)
    bytes[offset + i] = static_cast<std::uint8_t>(value >> (24 - 8 * i));
}
void append_be(Bytes& bytes, std::uint64_t value, int size) {
  for (int i = size - 1; i >= 0; --i)
    bytes.push_back(static_cast<std::uint8_t>(value >> (8 * i)));
}

// Offsets in the LCM encoding of msgs/rigid.lcm (after the 8-byte fingerprint).
constexpr std::size_t kStateNumBodies = 8;
constexpr std::size_t kStateNumXyz = 12;
constexpr std::size_t kWrenchBodyNameLength = 32;  // source, seq, key, body_id before it

TEST(LcmDecode, EmptyAndShortPayloadsAreTruncated) {
  lcm::Codec codec;
  StateFrame state;
  EXPECT_EQ(codec.decode({}, state), DecodeStatus::kTruncated);
  const Bytes four{1, 2, 3, 4};
  EXPECT_EQ(codec.decode(four, state), DecodeStatus::kTruncated);
}

TEST(LcmDecode, EveryTruncationOfAValidPayloadIsRejected) {
  lcm::Codec codec;
  RandomMessages random(3);
  const Bytes state_bytes = encode(codec, random.state(4));
  StateFrame state;
  for (std::size_t size = 0; size < state_bytes.size(); ++size) {
    const Bytes cut(state_bytes.begin(), state_bytes.begin() + static_cast<std::ptrdiff_t>(size));
    EXPECT_EQ(codec.decode(cut, state), DecodeStatus::kTruncated) << size << " bytes";
  }
  const Bytes scene_bytes = encode(codec, random.scene(3));
  SceneDescription scene;
  for (std::size_t size = 0; size < scene_bytes.size(); ++size) {
    const Bytes cut(scene_bytes.begin(), scene_bytes.begin() + static_cast<std::ptrdiff_t>(size));
    EXPECT_NE(codec.decode(cut, scene), DecodeStatus::kOk) << size << " bytes";
  }
}

TEST(LcmDecode, AnotherTypesPayloadHasTheWrongFingerprint) {
  lcm::Codec codec;
  RandomMessages random(4);
  const Bytes wrench_bytes = encode(codec, random.wrench());
  StateFrame state;
  EXPECT_EQ(codec.decode(wrench_bytes, state), DecodeStatus::kWrongFingerprint);
  ControlCommand control;
  EXPECT_EQ(codec.decode(wrench_bytes, control), DecodeStatus::kWrongFingerprint);

  Bytes flipped = encode(codec, random.control());
  flipped[3] ^= 0x10;
  EXPECT_EQ(codec.decode(flipped, control), DecodeStatus::kWrongFingerprint);
}

TEST(LcmDecode, NegativeCountIsABadCount) {
  lcm::Codec codec;
  RandomMessages random(5);
  Bytes bytes = encode(codec, random.state(2));
  put_be32(bytes, kStateNumBodies, 0xffffffffu);  // -1
  StateFrame state;
  EXPECT_EQ(codec.decode(bytes, state), DecodeStatus::kBadCount);
}

// A forged count must be refused from the payload size alone, before anything is allocated.
TEST(LcmDecode, HugeCountIsRefusedWithoutAllocating) {
  lcm::Codec codec;
  RandomMessages random(6);
  Bytes bytes = encode(codec, random.state(2));
  put_be32(bytes, kStateNumBodies, 0x7fffffffu);
  StateFrame state;
  EXPECT_EQ(codec.decode(bytes, state), DecodeStatus::kTruncated);
  put_be32(bytes, kStateNumBodies, 2);
  put_be32(bytes, kStateNumXyz, 0x7fffffffu);
  EXPECT_EQ(codec.decode(bytes, state), DecodeStatus::kTruncated);
}

// Well-formed LCM whose counts disagree with each other: 1 body but 3 orientation numbers.
TEST(LcmDecode, CountsThatDisagreeAreInconsistent) {
  lcm::Codec codec;
  const Bytes valid = encode(codec, StateFrame{});
  Bytes bytes(valid.begin(), valid.begin() + 8);  // the fingerprint
  append_be(bytes, 1, 4);                         // num_bodies
  append_be(bytes, 3, 4);                         // num_xyz
  append_be(bytes, 3, 4);                         // num_wxyz: should be 4
  append_be(bytes, 0, 8);                         // tick
  append_be(bytes, 0, 8);                         // sim_time
  append_be(bytes, 0, 8);                         // stamp_ns
  append_be(bytes, 0, 4);                         // ids[1]
  for (int i = 0; i < 3 + 3 + 3 + 3; ++i)
    append_be(bytes, 0, 8);  // the four arrays
  StateFrame state;
  EXPECT_EQ(codec.decode(bytes, state), DecodeStatus::kInconsistentLengths);
}

TEST(LcmDecode, ForgedStringLengthsAreRejected) {
  lcm::Codec codec;
  WrenchCommand wrench;
  wrench.body_name = "arm";
  const Bytes valid = encode(codec, wrench);
  WrenchCommand out;
  ASSERT_EQ(codec.decode(valid, out), DecodeStatus::kOk);

  // INT32_MIN: lcm-gen's decoder would compute length - 1 with signed overflow and read past
  // the buffer.
  Bytes bytes = valid;
  put_be32(bytes, kWrenchBodyNameLength, 0x80000000u);
  EXPECT_EQ(codec.decode(bytes, out), DecodeStatus::kMalformed);
  // 0: no room for the terminating NUL; lcm-gen's decoder would ask for a string of SIZE_MAX.
  put_be32(bytes, kWrenchBodyNameLength, 0);
  EXPECT_EQ(codec.decode(bytes, out), DecodeStatus::kMalformed);
  put_be32(bytes, kWrenchBodyNameLength, 0x7fffffffu);
  EXPECT_EQ(codec.decode(bytes, out), DecodeStatus::kTruncated);
  // The right length, but the terminator is not NUL.
  bytes = valid;
  bytes[kWrenchBodyNameLength + 4 + 3] = 'x';
  EXPECT_EQ(codec.decode(bytes, out), DecodeStatus::kMalformed);
  // A NUL inside the string ("a\0m"): lcm-gen's encoder would cut it at "a", so it could not be
  // sent on as it came (the fuzzer found one in Stats' refused_sender).
  bytes = valid;
  bytes[kWrenchBodyNameLength + 4 + 1] = 0;
  EXPECT_EQ(codec.decode(bytes, out), DecodeStatus::kMalformed);
}

TEST(LcmDecode, AStatsReportWithANulInASenderIsMalformed) {
  lcm::Codec codec;
  StatsReport stats;
  stats.refused_by_source.push_back({"alice", 3, "rate"});
  const Bytes valid = encode(codec, stats);
  ASSERT_FALSE(valid.empty());
  StatsReport out;
  ASSERT_EQ(codec.decode(valid, out), DecodeStatus::kOk);
  ASSERT_EQ(out.refused_by_source.at(0).sender, "alice");
  // "alice" with its terminator is 6 bytes: the only such run in the payload.
  const Bytes alice{'a', 'l', 'i', 'c', 'e', 0};
  const auto at = std::search(valid.begin(), valid.end(), alice.begin(), alice.end());
  ASSERT_NE(at, valid.end());
  Bytes bytes = valid;
  bytes[static_cast<std::size_t>(at - valid.begin()) + 2] = 0;
  EXPECT_EQ(codec.decode(bytes, out), DecodeStatus::kMalformed);
}

// A ContactEvents whose counts agree but exceed what one message may carry (4096 events).
TEST(LcmDecode, MoreContactEventsThanAMessageCarriesAreInconsistent) {
  lcm::Codec codec;
  const Bytes valid = encode(codec, ContactEvents{});
  for (const std::uint64_t n : {std::uint64_t{4096}, std::uint64_t{4097}}) {
    Bytes bytes(valid.begin(), valid.begin() + 8);  // the fingerprint
    append_be(bytes, n, 4);                         // num_events
    append_be(bytes, 3 * n, 4);                     // num_xyz
    for (int i = 0; i < 4; ++i)
      append_be(bytes, 0, 8);  // tick, sim_time, stamp_ns, dropped
    for (std::uint64_t i = 0; i < 3 * n; ++i)
      append_be(bytes, 1, 4);  // kinds, bodies, parts
    for (std::uint64_t i = 0; i < 10 * n; ++i)
      append_be(bytes, 0, 8);  // times and the three vectors
    ContactEvents out;
    EXPECT_EQ(codec.decode(bytes, out),
              n == 4096 ? DecodeStatus::kOk : DecodeStatus::kInconsistentLengths)
        << n << " events";
  }
}

// A SceneInfo whose part counts disagree: 2 parts but 3 position numbers.
TEST(LcmDecode, SceneInfoWithDisagreeingPartCountsIsInconsistent) {
  lcm::Codec codec;
  RandomMessages random(12);
  SceneDescription scene = random.scene(0, 2);
  Bytes bytes = encode(codec, scene);
  SceneDescription out;
  ASSERT_EQ(codec.decode(bytes, out), DecodeStatus::kOk);
  // num_part_xyz (after num_bodies, num_inertia, num_shape_dims, num_parts) 6 -> 3: the payload
  // then ends 24 bytes early for lcm-gen's layout, so the last 24 bytes are cut as well.
  put_be32(bytes, 8 + 4 * 4, 3);
  bytes.resize(bytes.size() - 2 * 24);  // part_position and part_dims shrink by 3 doubles each
  EXPECT_EQ(codec.decode(bytes, out), DecodeStatus::kInconsistentLengths);
}

TEST(LcmDecode, TrailingBytesAreMalformed) {
  lcm::Codec codec;
  Bytes bytes = encode(codec, ControlCommand{});
  bytes.push_back(0);
  ControlCommand out;
  EXPECT_EQ(codec.decode(bytes, out), DecodeStatus::kMalformed);
}

// Random bytes, and valid payloads with random bytes changed, on every message type: whatever
// the result, decoding returns.
template <class Codec>
void fuzz(Codec& codec, std::uint64_t seed) {
  RandomMessages random(seed);
  std::mt19937_64 rng(seed);
  StateFrame state;
  WrenchCommand wrench;
  ControlCommand control;
  ControlReply reply;
  StatsReport stats;
  SceneDescription scene;
  AcceptedCommand accepted;
  ContactEvents contacts;
  auto decode_all = [&](const Bytes& bytes) {
    (void)codec.decode(bytes, state);
    (void)codec.decode(bytes, wrench);
    (void)codec.decode(bytes, control);
    (void)codec.decode(bytes, reply);
    (void)codec.decode(bytes, stats);
    (void)codec.decode(bytes, scene);
    (void)codec.decode(bytes, accepted);
    (void)codec.decode(bytes, contacts);
  };
  const std::vector<Bytes> valid{
      encode(codec, random.state(5)),   encode(codec, random.wrench()),
      encode(codec, random.control()),  encode(codec, random.reply()),
      encode(codec, random.stats()),    encode(codec, random.scene(4, 3)),
      encode(codec, random.accepted()), encode(codec, random.contacts(4))};
  for (int round = 0; round < 3000; ++round) {
    Bytes bytes = valid[rng() % valid.size()];
    const int changes = 1 + static_cast<int>(rng() % 4);
    for (int c = 0; c < changes; ++c)
      bytes[rng() % bytes.size()] = static_cast<std::uint8_t>(rng());
    if (rng() % 4 == 0) bytes.resize(rng() % (bytes.size() + 1));
    decode_all(bytes);

    Bytes garbage(rng() % 300);
    for (auto& b : garbage)
      b = static_cast<std::uint8_t>(rng());
    decode_all(garbage);
  }
}

TEST(LcmDecode, CorruptedPayloadsNeverCrash) {
  lcm::Codec codec;
  fuzz(codec, 21);
}

TEST(DdsDecode, CorruptedPayloadsNeverCrash) {
  dds::CdrCodec codec;
  fuzz(codec, 22);
}

TEST(DdsDecode, TruncatedOrGarbagePayloadsAreMalformed) {
  dds::CdrCodec codec;
  RandomMessages random(8);
  const Bytes bytes = encode(codec, random.scene(3));
  SceneDescription scene;
  ASSERT_EQ(codec.decode(bytes, scene), DecodeStatus::kOk);
  const Bytes cut(bytes.begin(), bytes.end() - 3);
  EXPECT_EQ(codec.decode(cut, scene), DecodeStatus::kMalformed);
  Bytes forged = encode(codec, random.state(2));
  // The first sequence length (ids) follows tick, sim_time and stamp_ns (8 bytes each).
  const std::uint32_t huge = 0x7fffffff;
  std::memcpy(&forged[24], &huge, sizeof huge);
  StateFrame state;
  EXPECT_EQ(codec.decode(forged, state), DecodeStatus::kMalformed);
}

}  // namespace
}  // namespace rigid::transport
