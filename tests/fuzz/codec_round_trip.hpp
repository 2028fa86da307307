// What the bus fuzzers (fuzz_lcm_messages, fuzz_dds_messages) check on every payload that
// decodes, beyond "no crash, no undefined behaviour": the message can be sent on. Decoders promise
// per-body lengths that agree, so encoding it works, and encoding what that decodes to gives the
// same bytes.
#pragma once

#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include "fuzz_require.hpp"
#include "rigid/messages.hpp"
#include "transport/decode_status.hpp"

namespace rigid::fuzz {

// Decodes `bytes` as a Plain with `codec` (lcm::Codec or dds::CdrCodec) into `out`; true if it
// decoded. Checks that what decoded encodes again, stably.
template <class Codec, class Plain>
bool decode_checked(Codec& codec, std::span<const std::uint8_t> bytes, Plain& out) {
  if (codec.decode(bytes, out) != transport::DecodeStatus::kOk) return false;
  const std::span<const std::uint8_t> first = codec.encode(out);
  // LCM strings with an embedded NUL, which lcm-gen's encoder would cut, are refused by the
  // layout check; DDS strings end at their first NUL. So whatever decoded encodes.
  require(!first.empty(), "a message that decoded encodes again");
  // Copied: the span is valid only until the next encode of this type.
  const std::vector<std::uint8_t> encoded(first.begin(), first.end());
  Plain again;
  require(codec.decode(encoded, again) == transport::DecodeStatus::kOk,
          "a re-encoded message decodes");
  const std::span<const std::uint8_t> second = codec.encode(again);
  require(std::equal(encoded.begin(), encoded.end(), second.begin(), second.end()),
          "encoding a decoded message is stable");
  return true;
}

}  // namespace rigid::fuzz
