// Plain CDR (XCDR1, "CDR_LE"/"CDR_BE" encapsulation), the encoding ROS 2's DDS middlewares put on
// the wire for its keyless message types: a 4-byte encapsulation header (0x00 0x01 0x00 0x00 for
// little endian), then each field aligned to its own size (at most 8) counted from the end of the
// header; strings as a uint32 length that counts a terminating NUL, the bytes and the NUL;
// sequences as a uint32 count and the elements; fixed arrays as their elements alone (OMG
// DDS-XTypes 1.3, 7.4.1 "Extended CDR Representation", version 1).
//
// CdrWriter writes in this machine's byte order and says so in the header, as rmw_cyclonedds
// does. CdrReader reads either order and never reads past its bytes: every read checks, the first
// failure sticks, and the caller asks ok() once at the end.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "transport/decode_status.hpp"

namespace rigid::transport::ros {

inline constexpr std::size_t kCdrHeaderSize = 4;

class CdrWriter {
 public:
  // Writes into `out` (cleared first; its capacity is kept, so that a reused buffer stops
  // allocating once it has grown to the largest message).
  explicit CdrWriter(std::vector<std::uint8_t>& out) : out_(out) {
    const std::uint8_t little = std::endian::native == std::endian::little ? 1 : 0;
    out_.assign(kCdrHeaderSize, 0);
    out_[1] = little;
  }

  void u8(std::uint8_t v) { out_.push_back(v); }
  void boolean(bool v) { out_.push_back(v ? 1 : 0); }
  void u16(std::uint16_t v) { put(v); }
  void i32(std::int32_t v) { put(v); }
  void u32(std::uint32_t v) { put(v); }
  void i64(std::int64_t v) { put(v); }
  void u64(std::uint64_t v) { put(v); }
  void f32(float v) { put(v); }
  void f64(double v) { put(v); }
  // A sequence's element count; the caller writes the elements.
  void count(std::size_t n) { u32(static_cast<std::uint32_t>(n)); }
  void string(std::string_view s) {
    u32(static_cast<std::uint32_t>(s.size() + 1));
    append(s.data(), s.size());
    out_.push_back(0);
  }
  void bytes(std::span<const std::uint8_t> b) { append(b.data(), b.size()); }
  // Pads with zeros to a multiple of n counted from the end of the header.
  void align(std::size_t n) {
    const std::size_t at = out_.size() - kCdrHeaderSize;
    out_.resize(out_.size() + (n - at % n) % n, 0);
  }
  // Where the next byte goes (an index into the buffer, header included), aligned for a value of
  // n bytes: what a caller that patches values later keeps.
  std::size_t position_for(std::size_t n) {
    align(n);
    return out_.size();
  }
  std::size_t size() const { return out_.size(); }

 private:
  template <class T>
  void put(T v) {
    align(sizeof v);
    append(&v, sizeof v);
  }
  // resize and memcpy rather than insert: g++ 12 reports false bounds errors for the latter.
  void append(const void* data, std::size_t n) {
    if (n == 0) return;
    const std::size_t at = out_.size();
    out_.resize(at + n);
    std::memcpy(out_.data() + at, data, n);
  }
  std::vector<std::uint8_t>& out_;
};

class CdrReader {
 public:
  // `bytes` starts with the encapsulation header. A header other than plain CDR in either byte
  // order (XCDR2 or a parameter list, which no ROS 2 message type uses) fails at once.
  explicit CdrReader(std::span<const std::uint8_t> bytes);

  bool ok() const { return status_ == DecodeStatus::kOk; }
  DecodeStatus status() const { return status_; }
  // Bytes left after the last read (CDR allows trailing padding; callers decide).
  std::size_t remaining() const { return bytes_.size() - at_; }

  std::uint8_t u8();
  bool boolean();  // a byte other than 0 or 1 is malformed
  std::uint16_t u16() { return get<std::uint16_t>(); }
  std::int32_t i32() { return get<std::int32_t>(); }
  std::uint32_t u32() { return get<std::uint32_t>(); }
  std::int64_t i64() { return get<std::int64_t>(); }
  std::uint64_t u64() { return get<std::uint64_t>(); }
  float f32() { return get<float>(); }
  double f64() { return get<double>(); }
  // A string of at most max_length characters (NUL excluded) into `out` (its capacity reused). A
  // length beyond that, a missing terminator or a NUL inside is malformed.
  void string(std::string& out, std::size_t max_length);
  // Skips a string of at most max_length characters.
  void skip_string(std::size_t max_length);
  // A sequence's element count, at most max_count and at most what the remaining bytes can hold
  // at min_element_size bytes each (so a forged count never sizes an allocation).
  std::uint32_t count(std::uint32_t max_count, std::size_t min_element_size);
  void skip(std::size_t n);
  void fail(DecodeStatus status) {
    if (status_ == DecodeStatus::kOk) status_ = status;
  }

 private:
  bool align(std::size_t n);
  template <class T>
  T get() {
    T v{};
    if (!ok() || !align(sizeof v)) return v;
    if (remaining() < sizeof v) {
      fail(DecodeStatus::kTruncated);
      return v;
    }
    std::memcpy(&v, bytes_.data() + at_, sizeof v);
    at_ += sizeof v;
    if (swap_) v = byteswapped(v);
    return v;
  }
  template <class T>
  static T byteswapped(T v) {
    std::uint8_t raw[sizeof v];
    std::memcpy(raw, &v, sizeof v);
    for (std::size_t i = 0; i < sizeof v / 2; ++i)
      std::swap(raw[i], raw[sizeof v - 1 - i]);
    std::memcpy(&v, raw, sizeof v);
    return v;
  }

  std::span<const std::uint8_t> bytes_;
  std::size_t at_ = kCdrHeaderSize;
  bool swap_ = false;
  DecodeStatus status_ = DecodeStatus::kOk;
};

}  // namespace rigid::transport::ros
