#include "transport/ros/cdr.hpp"

namespace rigid::transport::ros {

CdrReader::CdrReader(std::span<const std::uint8_t> bytes) : bytes_(bytes) {
  if (bytes.size() < kCdrHeaderSize) {
    fail(DecodeStatus::kTruncated);
    at_ = bytes.size();
    return;
  }
  // Encapsulation identifiers (DDS-XTypes 1.3, 7.6.3.1.2): 0x0000 CDR_BE, 0x0001 CDR_LE. The two
  // option bytes carry padding hints only and are ignored.
  if (bytes[0] != 0x00 || bytes[1] > 0x01) {
    fail(DecodeStatus::kMalformed);
    return;
  }
  const bool little = bytes[1] == 0x01;
  swap_ = little != (std::endian::native == std::endian::little);
}

bool CdrReader::align(std::size_t n) {
  const std::size_t pad = (n - (at_ - kCdrHeaderSize) % n) % n;
  if (remaining() < pad) {
    fail(DecodeStatus::kTruncated);
    return false;
  }
  at_ += pad;
  return true;
}

std::uint8_t CdrReader::u8() {
  if (!ok()) return 0;
  if (remaining() < 1) {
    fail(DecodeStatus::kTruncated);
    return 0;
  }
  return bytes_[at_++];
}

bool CdrReader::boolean() {
  const std::uint8_t v = u8();
  if (v > 1) fail(DecodeStatus::kMalformed);
  return v == 1;
}

void CdrReader::string(std::string& out, std::size_t max_length) {
  out.clear();
  const std::uint32_t n = u32();
  if (!ok()) return;
  // The length counts the terminating NUL: 0 is malformed (rmw_cyclonedds writes 1 for "").
  if (n == 0 || n - 1 > max_length) {
    fail(n == 0 ? DecodeStatus::kMalformed : DecodeStatus::kBadCount);
    return;
  }
  if (remaining() < n) {
    fail(DecodeStatus::kTruncated);
    return;
  }
  const auto* text = reinterpret_cast<const char*>(bytes_.data() + at_);
  if (text[n - 1] != '\0' || std::memchr(text, '\0', n - 1) != nullptr) {
    fail(DecodeStatus::kMalformed);
    return;
  }
  out.assign(text, n - 1);
  at_ += n;
}

void CdrReader::skip_string(std::size_t max_length) {
  const std::uint32_t n = u32();
  if (!ok()) return;
  if (n == 0 || n - 1 > max_length) {
    fail(n == 0 ? DecodeStatus::kMalformed : DecodeStatus::kBadCount);
    return;
  }
  if (remaining() < n) {
    fail(DecodeStatus::kTruncated);
    return;
  }
  if (bytes_[at_ + n - 1] != 0) {
    fail(DecodeStatus::kMalformed);
    return;
  }
  at_ += n;
}

std::uint32_t CdrReader::count(std::uint32_t max_count, std::size_t min_element_size) {
  const std::uint32_t n = u32();
  if (!ok()) return 0;
  if (n > max_count || (min_element_size > 0 && n > remaining() / min_element_size)) {
    fail(DecodeStatus::kBadCount);
    return 0;
  }
  return n;
}

void CdrReader::skip(std::size_t n) {
  if (!ok()) return;
  if (remaining() < n) {
    fail(DecodeStatus::kTruncated);
    return;
  }
  at_ += n;
}

}  // namespace rigid::transport::ros
