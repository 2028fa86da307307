// A bounded JSON reader for the Foxglove WebSocket protocol's client messages (nested objects and
// arrays, string escapes), which the page's flat command reader (protocol.cpp) does not take.
// Bounded: the text's length is the caller's (the WebSocket's message limit); nesting at most
// kMaxJsonDepth, at most kMaxJsonValues values in all, so memory is linear in the text.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace rigid::view {

inline constexpr std::size_t kMaxJsonDepth = 8;
inline constexpr std::size_t kMaxJsonValues = 4096;

struct JsonField;

struct Json {
  enum class Kind { kNull, kBool, kNumber, kString, kArray, kObject };
  Kind kind = Kind::kNull;
  bool boolean = false;
  double number = 0;
  std::string text;               // kString, as UTF-8
  std::vector<Json> items;        // kArray
  std::vector<JsonField> fields;  // kObject, in the text's order

  // The member named `key` of an object (the first, if named twice), else nullptr.
  const Json* get(std::string_view key) const;
};

struct JsonField {
  std::string key;
  Json value;
};

// The value of `text` (one JSON value, whitespace around it allowed), or one line saying where
// and why it is not JSON or is beyond the bounds.
std::variant<Json, std::string> parse_json(std::string_view text);

}  // namespace rigid::view
