// Every message, with random values, through each bus's representation and back:
//   plain -> idlc C type -> CDR bytes -> idlc C type -> plain   (dds::CdrCodec)
//   plain -> lcm-gen C++ type -> LCM bytes -> lcm-gen type -> plain   (lcm::Codec)
// must come back exactly. No network is involved.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "random_messages.hpp"
#include "transport/dds/dds_cdr_codec.hpp"
#include "transport/lcm/lcm_codec.hpp"
#include "transport/lcm/lcm_convert.hpp"

namespace rigid::transport {
namespace {

using testing::RandomMessages;

// Each check below runs once per codec (the TESTs at the end).
template <class Codec, class Message>
void expect_round_trip(Codec& codec, const Message& message) {
  const std::span<const std::uint8_t> encoded = codec.encode(message);
  ASSERT_FALSE(encoded.empty());
  // Decode from a copy: the encode buffer is the codec's own.
  const std::vector<std::uint8_t> bytes(encoded.begin(), encoded.end());
  Message decoded;
  ASSERT_EQ(codec.decode(bytes, decoded), DecodeStatus::kOk);
  EXPECT_EQ(decoded, message);
}

template <class Codec>
void every_message_with_random_values_comes_back_exactly() {
  Codec codec;
  for (std::uint64_t seed = 1; seed <= 200; ++seed) {
    SCOPED_TRACE(::testing::Message() << "seed " << seed);
    RandomMessages random(seed);
    const std::size_t bodies = random.below(20);
    expect_round_trip(codec, random.state(bodies));
    expect_round_trip(codec, random.wrench());
    expect_round_trip(codec, random.control());
    expect_round_trip(codec, random.reply());
    expect_round_trip(codec, random.stats());
    expect_round_trip(codec, random.scene(bodies));
    expect_round_trip(codec, random.accepted());
    expect_round_trip(codec, random.contacts(random.below(50)));
    expect_round_trip(codec, random.edit());
  }
}

template <class Codec>
void empty_messages_come_back() {
  Codec codec;
  expect_round_trip(codec, StateFrame{});
  expect_round_trip(codec, WrenchCommand{});
  expect_round_trip(codec, ControlCommand{});
  expect_round_trip(codec, ControlReply{});
  expect_round_trip(codec, StatsReport{});
  expect_round_trip(codec, SceneDescription{});
  expect_round_trip(codec, AcceptedCommand{});
  expect_round_trip(codec, ContactEvents{});
  expect_round_trip(codec, EditCommand{});
}

template <class Codec>
void thousand_body_state_comes_back() {
  Codec codec;
  RandomMessages random(7);
  expect_round_trip(codec, random.state(1000));
  expect_round_trip(codec, random.scene(1000, 1000));
  expect_round_trip(codec, random.contacts(kMaxContactEvents));
}

// Infinities, NaNs with payloads and negative zero are compared bit for bit (== cannot).
template <class Codec>
void special_doubles_come_back_bit_for_bit() {
  Codec codec;
  const std::vector<double> specials{std::numeric_limits<double>::infinity(),
                                     -std::numeric_limits<double>::infinity(),
                                     std::bit_cast<double>(std::uint64_t{0x7ff8'0000'dead'beef}),
                                     std::bit_cast<double>(std::uint64_t{0xfff0'0000'0000'0001}),
                                     -0.0,
                                     std::numeric_limits<double>::denorm_min(),
                                     std::numeric_limits<double>::max()};
  StateFrame state;
  state.resize(specials.size());
  for (std::size_t i = 0; i < specials.size(); ++i) {
    state.position[3 * i + 1] = specials[i];
    state.orientation[4 * i + 2] = specials[i];
    state.angular_velocity[3 * i] = specials[i];
  }
  state.sim_time = specials[2];
  const auto encoded = codec.encode(state);
  const std::vector<std::uint8_t> bytes(encoded.begin(), encoded.end());
  StateFrame decoded;
  ASSERT_EQ(codec.decode(bytes, decoded), DecodeStatus::kOk);
  auto bits = [](const std::vector<double>& v) {
    std::vector<std::uint64_t> out;
    for (double x : v)
      out.push_back(std::bit_cast<std::uint64_t>(x));
    return out;
  };
  EXPECT_EQ(bits(decoded.position), bits(state.position));
  EXPECT_EQ(bits(decoded.orientation), bits(state.orientation));
  EXPECT_EQ(bits(decoded.angular_velocity), bits(state.angular_velocity));
  EXPECT_EQ(std::bit_cast<std::uint64_t>(decoded.sim_time),
            std::bit_cast<std::uint64_t>(state.sim_time));
}

// Decoding reuses the output's storage: a smaller message after a larger one must not keep any
// of the larger one's elements.
template <class Codec>
void reused_output_holds_only_the_latest_message() {
  Codec codec;
  RandomMessages random(11);
  StateFrame out;
  SceneDescription scene_out;
  ContactEvents contacts_out;
  for (std::size_t bodies : {30u, 3u, 0u, 12u}) {
    const StateFrame state = random.state(bodies);
    const auto encoded = codec.encode(state);
    const std::vector<std::uint8_t> bytes(encoded.begin(), encoded.end());
    ASSERT_EQ(codec.decode(bytes, out), DecodeStatus::kOk);
    EXPECT_EQ(out, state);

    const SceneDescription scene = random.scene(bodies);
    const auto scene_encoded = codec.encode(scene);
    const std::vector<std::uint8_t> scene_bytes(scene_encoded.begin(), scene_encoded.end());
    ASSERT_EQ(codec.decode(scene_bytes, scene_out), DecodeStatus::kOk);
    EXPECT_EQ(scene_out, scene);

    const ContactEvents contacts = random.contacts(bodies);
    const auto contacts_encoded = codec.encode(contacts);
    const std::vector<std::uint8_t> contacts_bytes(contacts_encoded.begin(),
                                                   contacts_encoded.end());
    ASSERT_EQ(codec.decode(contacts_bytes, contacts_out), DecodeStatus::kOk);
    EXPECT_EQ(contacts_out, contacts);
  }
}

template <class Codec>
void inconsistent_message_is_not_encoded() {
  Codec codec;
  StateFrame state;
  state.resize(2);
  state.orientation.pop_back();
  EXPECT_TRUE(codec.encode(state).empty());
  SceneDescription scene;
  scene.ids = {1, 2};
  scene.names = {"a"};
  EXPECT_TRUE(codec.encode(scene).empty());
  RandomMessages random(5);
  SceneDescription parts = random.scene(2, 3);
  parts.part_orientation.pop_back();
  EXPECT_TRUE(codec.encode(parts).empty());
  parts = random.scene(2, 3);
  parts.part_friction.push_back(0.5);
  EXPECT_TRUE(codec.encode(parts).empty());
  ContactEvents contacts = random.contacts(3);
  contacts.impulse.pop_back();
  EXPECT_TRUE(codec.encode(contacts).empty());
  // More events than a message may carry.
  EXPECT_TRUE(codec.encode(random.contacts(kMaxContactEvents + 1)).empty());
}

TEST(DdsRoundTrip, EveryMessageWithRandomValuesComesBackExactly) {
  every_message_with_random_values_comes_back_exactly<dds::CdrCodec>();
}
TEST(LcmRoundTrip, EveryMessageWithRandomValuesComesBackExactly) {
  every_message_with_random_values_comes_back_exactly<lcm::Codec>();
}

TEST(DdsRoundTrip, EmptyMessagesComeBack) {
  empty_messages_come_back<dds::CdrCodec>();
}
TEST(LcmRoundTrip, EmptyMessagesComeBack) {
  empty_messages_come_back<lcm::Codec>();
}

TEST(DdsRoundTrip, ThousandBodyStateComesBack) {
  thousand_body_state_comes_back<dds::CdrCodec>();
}
TEST(LcmRoundTrip, ThousandBodyStateComesBack) {
  thousand_body_state_comes_back<lcm::Codec>();
}

TEST(DdsRoundTrip, SpecialDoublesComeBackBitForBit) {
  special_doubles_come_back_bit_for_bit<dds::CdrCodec>();
}
TEST(LcmRoundTrip, SpecialDoublesComeBackBitForBit) {
  special_doubles_come_back_bit_for_bit<lcm::Codec>();
}

TEST(DdsRoundTrip, ReusedOutputHoldsOnlyTheLatestMessage) {
  reused_output_holds_only_the_latest_message<dds::CdrCodec>();
}
TEST(LcmRoundTrip, ReusedOutputHoldsOnlyTheLatestMessage) {
  reused_output_holds_only_the_latest_message<lcm::Codec>();
}

TEST(DdsRoundTrip, InconsistentMessageIsNotEncoded) {
  inconsistent_message_is_not_encoded<dds::CdrCodec>();
}
TEST(LcmRoundTrip, InconsistentMessageIsNotEncoded) {
  inconsistent_message_is_not_encoded<lcm::Codec>();
}

// lcm::Codec writes a state and a scene straight from rigid's types (lcm_codec.cpp); lcm-gen's
// encoder, fed the same message through its own type, is the reference for every byte.
template <class LcmType, class Message>
void expect_generated_bytes(lcm::Codec& codec, const Message& message) {
  LcmType generated;
  ASSERT_TRUE(lcm::to_lcm(message, generated));
  std::vector<std::uint8_t> expected(static_cast<std::size_t>(generated.getEncodedSize()));
  ASSERT_EQ(generated.encode(expected.data(), 0, static_cast<int>(expected.size())),
            static_cast<int>(expected.size()));
  const std::span<const std::uint8_t> encoded = codec.encode(message);
  ASSERT_EQ(std::vector<std::uint8_t>(encoded.begin(), encoded.end()), expected);
}

TEST(LcmStateEncoding, BytesAreThoseOfTheGeneratedEncoder) {
  lcm::Codec codec;
  for (std::uint64_t seed = 1; seed <= 50; ++seed) {
    SCOPED_TRACE(::testing::Message() << "seed " << seed);
    RandomMessages random(seed);
    StateFrame state = random.state(seed == 1 ? 0 : random.below(seed < 40 ? 20 : 3000));
    if (seed % 5 == 0 && state.body_count() > 0) {
      state.position[0] = std::numeric_limits<double>::quiet_NaN();
      state.orientation[0] = -std::numeric_limits<double>::infinity();
      state.linear_velocity[0] = -0.0;
    }
    expect_generated_bytes<rigid_lcm::WorldState>(codec, state);
  }
}

TEST(LcmSceneEncoding, BytesAreThoseOfTheGeneratedEncoder) {
  lcm::Codec codec;
  for (std::uint64_t seed = 1; seed <= 50; ++seed) {
    SCOPED_TRACE(::testing::Message() << "seed " << seed);
    RandomMessages random(seed);
    SceneDescription scene = random.scene(seed == 1 ? 0 : random.below(seed < 40 ? 20 : 3000));
    // The fields the generator leaves at zero, so that a swap among them shows.
    scene.max_ttl = 0.25 * static_cast<double>(seed);
    scene.max_wrenches_per_source = static_cast<std::int32_t>(seed) + 7;
    scene.max_commands_per_second = 1000.5 + static_cast<double>(seed);
    if (seed % 5 == 0 && scene.body_count() > 0) {
      scene.masses[0] = std::numeric_limits<double>::quiet_NaN();
      scene.names[0].clear();
      scene.scene_name.clear();
    }
    if (seed % 7 == 0 && scene.part_count() > 0) {
      scene.part_names[0].clear();
      scene.part_friction[0] = -0.0;
    }
    expect_generated_bytes<rigid_lcm::SceneInfo>(codec, scene);
  }
}

TEST(LcmSceneEncoding, AStringHoldingANulOrDisagreeingLengthsAreRefusedKeepingTheLastPayload) {
  lcm::Codec codec;
  RandomMessages random(3);
  const SceneDescription good = random.scene(4);
  const std::span<const std::uint8_t> kept = codec.encode(good);
  ASSERT_FALSE(kept.empty());
  const std::vector<std::uint8_t> good_bytes(kept.begin(), kept.end());
  SceneDescription bad = good;
  bad.names[2] = std::string("ra\0cket", 7);
  EXPECT_TRUE(codec.encode(bad).empty());
  bad = good;
  bad.integrator.push_back('\0');
  EXPECT_TRUE(codec.encode(bad).empty());
  bad = good;
  bad.inertia.pop_back();
  EXPECT_TRUE(codec.encode(bad).empty());
  bad = good;
  bad.part_names.push_back(std::string("gr\0und", 7));
  bad.part_kinds.push_back(ShapeKind::kPlane);
  bad.part_position.insert(bad.part_position.end(), 3, 0.0);
  bad.part_orientation.insert(bad.part_orientation.end(), {1.0, 0.0, 0.0, 0.0});
  bad.part_dims.insert(bad.part_dims.end(), 3, 0.0);
  bad.part_restitution.push_back(0.0);
  bad.part_friction.push_back(0.5);
  ASSERT_TRUE(bad.lengths_agree());
  EXPECT_TRUE(codec.encode(bad).empty());
  // A refused scene leaves the last payload as it was (the LCM transport republishes it).
  EXPECT_EQ(std::vector<std::uint8_t>(kept.begin(), kept.end()), good_bytes);
  // And the good one still decodes as itself after the refusals.
  SceneDescription decoded;
  ASSERT_EQ(codec.decode(codec.encode(good), decoded), DecodeStatus::kOk);
  EXPECT_EQ(decoded, good);
}

}  // namespace
}  // namespace rigid::transport
