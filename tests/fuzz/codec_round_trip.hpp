// What the bus fuzzers (fuzz_lcm_messages, fuzz_dds_messages) check on every payload that
// decodes, beyond "no crash, no undefined behaviour": the message can be sent on. Decoders promise
// per-body lengths that agree, so encoding it works, and encoding what that decodes to gives the
// same bytes.
#pragma once

#include <algorithm>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "fuzz_require.hpp"
#include "rigid/messages.hpp"
#include "transport/decode_status.hpp"

namespace rigid::fuzz {

// LCM strings are C strings: lcm-gen's decoder keeps bytes after an embedded NUL but its encoder
// stops at the first one, so such a message decodes but cannot be encoded again (Codec::encode
// then returns nothing). Only messages with strings can be in that case.
template <class Plain>
bool has_embedded_nul(const Plain& /*message*/) {
  return false;
}
inline bool nul_in(const std::string& s) {
  return s.find('\0') != std::string::npos;
}
inline bool has_embedded_nul(const rigid::WrenchCommand& m) {
  return nul_in(m.body_name);
}
inline bool has_embedded_nul(const rigid::ControlReply& m) {
  return nul_in(m.message);
}
inline bool has_embedded_nul(const rigid::SceneDescription& m) {
  return nul_in(m.scene_name) || nul_in(m.integrator) ||
         std::any_of(m.names.begin(), m.names.end(), nul_in);
}

// Decodes `bytes` as a Plain with `codec` (lcm::Codec or dds::CdrCodec) into `out`; true if it
// decoded. Checks that what decoded encodes again, stably.
template <class Codec, class Plain>
bool decode_checked(Codec& codec, std::span<const std::uint8_t> bytes, Plain& out) {
  if (codec.decode(bytes, out) != transport::DecodeStatus::kOk) return false;
  const std::span<const std::uint8_t> first = codec.encode(out);
  if (first.empty()) {
    require(has_embedded_nul(out), "a message that decoded encodes again");
    return true;
  }
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
