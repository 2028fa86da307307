// rigid's messages as LCM payloads (msgs/rigid.lcm), both ways, for the LCM transport and for tools
// that read LCM logs. Encoding and decoding reuse internal buffers: after the first messages of the
// largest size they allocate nothing.
//
// Thread safety: one codec may encode one type while it encodes another type, or decodes, on other
// threads; the same type must not be encoded (or decoded) on two threads at once.
#pragma once

#include <cstdint>
#include <memory>
#include <span>

#include "rigid/messages.hpp"
#include "transport/decode_status.hpp"

namespace rigid::transport::lcm {

class Codec {
 public:
  Codec();
  ~Codec();
  Codec(const Codec&) = delete;
  Codec& operator=(const Codec&) = delete;

  // The encoded payload (fingerprint first), valid until the next encode of the same type. Empty if
  // the message's per-body arrays disagree with its body count. A scene refused so leaves the
  // previous scene's payload valid (the LCM transport republishes it).
  std::span<const std::uint8_t> encode(const StateFrame& message);
  std::span<const std::uint8_t> encode(const WrenchCommand& message);
  std::span<const std::uint8_t> encode(const ControlCommand& message);
  std::span<const std::uint8_t> encode(const ControlReply& message);
  std::span<const std::uint8_t> encode(const StatsReport& message);
  std::span<const std::uint8_t> encode(const SceneDescription& message);
  std::span<const std::uint8_t> encode(const AcceptedCommand& message);

  // Fills `out` (reusing its storage) and returns kOk, or returns why not; `out` is then
  // unspecified but valid. Never throws on bad input.
  DecodeStatus decode(std::span<const std::uint8_t> payload, StateFrame& out);
  DecodeStatus decode(std::span<const std::uint8_t> payload, WrenchCommand& out);
  DecodeStatus decode(std::span<const std::uint8_t> payload, ControlCommand& out);
  DecodeStatus decode(std::span<const std::uint8_t> payload, ControlReply& out);
  DecodeStatus decode(std::span<const std::uint8_t> payload, StatsReport& out);
  DecodeStatus decode(std::span<const std::uint8_t> payload, SceneDescription& out);
  DecodeStatus decode(std::span<const std::uint8_t> payload, AcceptedCommand& out);

 private:
  struct Buffers;
  std::unique_ptr<Buffers> buffers_;
};

}  // namespace rigid::transport::lcm
