// Why a received payload was not turned into a message. Decoding never throws and never crashes on
// bad input: it returns one of these, and the transport reports it to its Receiver.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "rigid/messages.hpp"
#include "transport/topic.hpp"

namespace rigid::transport {

enum class DecodeStatus : std::uint8_t {
  kOk = 0,
  kTruncated,            // the payload ends before the message does
  kWrongFingerprint,     // LCM: the payload is another type (or another version of this one)
  kBadCount,             // a length field is negative or larger than the payload can hold
  kInconsistentLengths,  // per-body arrays disagree with the number of bodies
  kMalformed,            // anything else the decoder refused (bad string, trailing bytes, ...)
};

std::string_view to_string(DecodeStatus status);

// A payload that arrived on `topic` of `bus` and did not decode.
struct DecodeError {
  Bus bus = Bus::kDds;
  Topic topic = Topic::kState;
  DecodeStatus status = DecodeStatus::kMalformed;
  std::size_t payload_size = 0;  // bytes (0 where the bus does not expose them)
};

}  // namespace rigid::transport
