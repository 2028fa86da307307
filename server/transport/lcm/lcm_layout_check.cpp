#include "transport/lcm/lcm_layout_check.hpp"

#include <array>
#include <cstddef>
#include <cstring>

namespace rigid::transport::lcm {
namespace {

// LCM encodes every integer big-endian.
std::uint64_t read_be(const std::uint8_t* p, std::size_t bytes) {
  std::uint64_t v = 0;
  for (std::size_t i = 0; i < bytes; ++i)
    v = (v << 8) | p[i];
  return v;
}

std::int32_t read_i32(const std::uint8_t* p) {
  return static_cast<std::int32_t>(static_cast<std::uint32_t>(read_be(p, 4)));
}

std::size_t element_size(FieldLayout::Kind kind) {
  switch (kind) {
    case FieldLayout::Kind::kInt8:
      return 1;
    case FieldLayout::Kind::kInt32:
    case FieldLayout::Kind::kCount:
      return 4;
    case FieldLayout::Kind::kInt64:
    case FieldLayout::Kind::kDouble:
      return 8;
    case FieldLayout::Kind::kString:
      return 4;  // the length prefix; the body is checked separately
  }
  return 1;
}

// More count fields than any rigid type declares.
constexpr std::size_t kMaxCounts = 8;

}  // namespace

DecodeStatus check_layout(std::span<const std::uint8_t> payload, std::int64_t fingerprint,
                          std::span<const FieldLayout> layout) {
  const std::size_t size = payload.size();
  const std::uint8_t* data = payload.data();
  if (size < 8) return DecodeStatus::kTruncated;
  if (static_cast<std::int64_t>(read_be(data, 8)) != fingerprint) {
    return DecodeStatus::kWrongFingerprint;
  }
  std::size_t pos = 8;
  std::array<std::int32_t, kMaxCounts> counts{};
  std::size_t num_counts = 0;

  for (const FieldLayout& field : layout) {
    std::int64_t n = field.fixed;
    if (field.count_field >= 0) {
      if (static_cast<std::size_t>(field.count_field) >= num_counts)
        return DecodeStatus::kMalformed;
      n = counts[static_cast<std::size_t>(field.count_field)];
    }
    const std::size_t elem = element_size(field.kind);
    // Every element takes at least `elem` bytes, so this bounds n before any loop runs over it.
    if (static_cast<std::uint64_t>(n) * elem > size - pos) return DecodeStatus::kTruncated;

    if (field.kind == FieldLayout::Kind::kCount) {
      if (num_counts == kMaxCounts) return DecodeStatus::kMalformed;
      const std::int32_t count = read_i32(data + pos);
      if (count < 0) return DecodeStatus::kBadCount;
      counts[num_counts++] = count;
      pos += 4;
    } else if (field.kind == FieldLayout::Kind::kString) {
      for (std::int64_t i = 0; i < n; ++i) {
        if (size - pos < 4) return DecodeStatus::kTruncated;
        const std::int32_t length = read_i32(data + pos);
        pos += 4;
        // The length counts the terminating NUL, which must be there.
        if (length < 1) return DecodeStatus::kMalformed;
        if (static_cast<std::size_t>(length) > size - pos) return DecodeStatus::kTruncated;
        if (data[pos + static_cast<std::size_t>(length) - 1] != 0) return DecodeStatus::kMalformed;
        // Nor a NUL before it: LCM strings are C strings. lcm-gen's decoder would keep the bytes
        // after an embedded NUL and its encoder drop them, so the message could not be sent on
        // (or recorded and replayed) as it arrived.
        if (std::memchr(data + pos, 0, static_cast<std::size_t>(length) - 1) != nullptr) {
          return DecodeStatus::kMalformed;
        }
        pos += static_cast<std::size_t>(length);
      }
    } else {
      pos += static_cast<std::size_t>(n) * elem;
    }
  }
  return pos == size ? DecodeStatus::kOk : DecodeStatus::kMalformed;
}

}  // namespace rigid::transport::lcm
