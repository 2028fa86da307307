// rigid's messages as Cyclone DDS serializes them (XCDR1, native byte order, without the 4-byte
// encapsulation header a DDS sample carries on the wire): what dds_write puts in a datagram, for
// tests and measurements that want the bytes without a network. The transport itself lets Cyclone
// serialize; it does not use this.
//
// Thread safety: like lcm::Codec, one type at a time per thread.
#pragma once

#include <cstdint>
#include <memory>
#include <span>

#include "rigid/messages.hpp"
#include "transport/decode_status.hpp"

namespace rigid::transport::dds {

class CdrCodec {
 public:
  CdrCodec();
  ~CdrCodec();
  CdrCodec(const CdrCodec&) = delete;
  CdrCodec& operator=(const CdrCodec&) = delete;

  // The serialized message, valid until the next encode of the same type. Empty if the message's
  // per-body arrays disagree with its body count.
  std::span<const std::uint8_t> encode(const StateFrame& message);
  std::span<const std::uint8_t> encode(const WrenchCommand& message);
  std::span<const std::uint8_t> encode(const ControlCommand& message);
  std::span<const std::uint8_t> encode(const ControlReply& message);
  std::span<const std::uint8_t> encode(const StatsReport& message);
  std::span<const std::uint8_t> encode(const SceneDescription& message);
  std::span<const std::uint8_t> encode(const AcceptedCommand& message);

  // Validates the bytes the way Cyclone validates a received sample, then deserializes into the
  // idlc type and copies into `out`. Never crashes on bad input.
  DecodeStatus decode(std::span<const std::uint8_t> bytes, StateFrame& out);
  DecodeStatus decode(std::span<const std::uint8_t> bytes, WrenchCommand& out);
  DecodeStatus decode(std::span<const std::uint8_t> bytes, ControlCommand& out);
  DecodeStatus decode(std::span<const std::uint8_t> bytes, ControlReply& out);
  DecodeStatus decode(std::span<const std::uint8_t> bytes, StatsReport& out);
  DecodeStatus decode(std::span<const std::uint8_t> bytes, SceneDescription& out);
  DecodeStatus decode(std::span<const std::uint8_t> bytes, AcceptedCommand& out);

 private:
  struct Buffers;
  std::unique_ptr<Buffers> buffers_;
};

}  // namespace rigid::transport::dds
