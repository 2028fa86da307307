// Checks an LCM payload against the layout of its type before lcm-gen's decoder sees it.
// Why: the generated C++ decoder trusts length fields. A forged array count makes it resize a
// vector to billions of elements, and a forged string length of INT32_MIN overflows and reads past
// the buffer. Walking the payload once against the declared layout (cheap: it only reads the length
// fields) turns every such payload into a typed DecodeStatus instead.
#pragma once

#include <cstdint>
#include <span>

#include "transport/decode_status.hpp"

namespace rigid::transport::lcm {

// One field of an LCM struct, as encoded (nested structs are listed field by field: LCM encodes
// them inline without their own fingerprint).
struct FieldLayout {
  enum class Kind : std::uint8_t {
    kInt8,  // also boolean
    kInt32,
    kInt64,
    kDouble,
    kString,  // int32 length including the terminating NUL, then the bytes
    kCount,   // an int32 that sizes later arrays; must be >= 0
  };
  Kind kind;
  // Number of elements: `fixed` when count_field < 0, else the value of the count_field-th kCount
  // field (0-based, in order of appearance).
  std::int32_t fixed = 1;
  std::int32_t count_field = -1;
};

// Checks fingerprint, then every length against the bytes that remain, and that the payload ends
// exactly where the message does. kOk means lcm-gen's decode cannot run out of bounds on it.
DecodeStatus check_layout(std::span<const std::uint8_t> payload, std::int64_t fingerprint,
                          std::span<const FieldLayout> layout);

}  // namespace rigid::transport::lcm
