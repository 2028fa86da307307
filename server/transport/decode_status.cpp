#include "transport/decode_status.hpp"

namespace rigid::transport {

std::string_view to_string(DecodeStatus status) {
  switch (status) {
    case DecodeStatus::kOk:
      return "ok";
    case DecodeStatus::kTruncated:
      return "truncated payload";
    case DecodeStatus::kWrongFingerprint:
      return "wrong type fingerprint";
    case DecodeStatus::kBadCount:
      return "array length out of range";
    case DecodeStatus::kInconsistentLengths:
      return "per-body arrays disagree with the body count";
    case DecodeStatus::kMalformed:
      return "malformed payload";
  }
  return "unknown decode status";
}

}  // namespace rigid::transport
