// rigid's messages as one bus's bytes, both ways, declared once for every bus: Codec<Bus::kLcm>
// (lcm::Codec, LCM payloads with their fingerprint, for the LCM transport and for tools that read
// LCM logs) and Codec<Bus::kDds> (dds::CdrCodec, XCDR1 as Cyclone DDS serializes a sample, for
// tests and measurements that want the bytes without a network). Each bus's library defines its
// own (transport/codec_impl.hpp); the bus headers (lcm/lcm_codec.hpp, dds/dds_cdr_codec.hpp) say
// what their bytes are.
//
// Encoding and decoding reuse internal buffers: after the first messages of the largest size they
// allocate nothing. Thread safety: one codec may encode one type while it encodes another type, or
// decodes, on other threads; the same type must not be encoded (or decoded) on two threads at once.
#pragma once

#include <cstdint>
#include <memory>
#include <span>

#include "rigid/messages.hpp"
#include "transport/decode_status.hpp"

namespace rigid::transport {

// Each bus's buffers (defined by its codec's source file).
template <Bus B>
struct CodecBuffers;

template <Bus B>
class Codec {
 public:
  Codec();
  ~Codec();
  Codec(const Codec&) = delete;
  Codec& operator=(const Codec&) = delete;

  // The encoded message, valid until the next encode of the same type. Empty if the message's
  // per-body arrays disagree with its body count (or a string exceeds its bound).
  std::span<const std::uint8_t> encode(const StateFrame& message);
  std::span<const std::uint8_t> encode(const WrenchCommand& message);
  std::span<const std::uint8_t> encode(const ControlCommand& message);
  std::span<const std::uint8_t> encode(const ControlReply& message);
  std::span<const std::uint8_t> encode(const StatsReport& message);
  std::span<const std::uint8_t> encode(const SceneDescription& message);
  std::span<const std::uint8_t> encode(const AcceptedCommand& message);
  std::span<const std::uint8_t> encode(const ContactEvents& message);
  std::span<const std::uint8_t> encode(const EditCommand& message);

  // Fills `out` (reusing its storage) and returns kOk, or returns why not; `out` is then
  // unspecified but valid. Never throws or crashes on bad input.
  DecodeStatus decode(std::span<const std::uint8_t> bytes, StateFrame& out);
  DecodeStatus decode(std::span<const std::uint8_t> bytes, WrenchCommand& out);
  DecodeStatus decode(std::span<const std::uint8_t> bytes, ControlCommand& out);
  DecodeStatus decode(std::span<const std::uint8_t> bytes, ControlReply& out);
  DecodeStatus decode(std::span<const std::uint8_t> bytes, StatsReport& out);
  DecodeStatus decode(std::span<const std::uint8_t> bytes, SceneDescription& out);
  DecodeStatus decode(std::span<const std::uint8_t> bytes, AcceptedCommand& out);
  DecodeStatus decode(std::span<const std::uint8_t> bytes, ContactEvents& out);
  DecodeStatus decode(std::span<const std::uint8_t> bytes, EditCommand& out);

 private:
  std::unique_ptr<CodecBuffers<B>> buffers_;
};

}  // namespace rigid::transport
