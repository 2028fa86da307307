#include "json_value.hpp"

#include <cmath>
#include <cstdint>
#include <cstdlib>

namespace rigid::view {
namespace {

class Parser {
 public:
  explicit Parser(std::string_view s) : s_(s) {}

  std::string parse(Json& out) {
    ws();
    if (!value(out, 0)) return error_;
    ws();
    if (i_ != s_.size()) return at("trailing bytes after the value");
    return {};
  }

 private:
  bool fail(const std::string& why) {
    if (error_.empty()) error_ = at(why);
    return false;
  }
  std::string at(const std::string& why) const {
    return "JSON: " + why + " at byte " + std::to_string(i_);
  }
  char peek() const { return i_ < s_.size() ? s_[i_] : '\0'; }
  bool eat(char c) {
    if (peek() != c) return false;
    ++i_;
    return true;
  }
  void ws() {
    while (i_ < s_.size() && (s_[i_] == ' ' || s_[i_] == '\n' || s_[i_] == '\t' || s_[i_] == '\r'))
      ++i_;
  }
  bool literal(std::string_view word) {
    if (s_.substr(i_, word.size()) != word) return fail("expected a value");
    i_ += word.size();
    return true;
  }

  bool value(Json& out, std::size_t depth) {
    if (++values_ > kMaxJsonValues)
      return fail("more than " + std::to_string(kMaxJsonValues) + " values");
    switch (peek()) {
      case '{':
        return object(out, depth + 1);
      case '[':
        return array(out, depth + 1);
      case '"':
        out.kind = Json::Kind::kString;
        return string(out.text);
      case 't':
        out.kind = Json::Kind::kBool;
        out.boolean = true;
        return literal("true");
      case 'f':
        out.kind = Json::Kind::kBool;
        return literal("false");
      case 'n':
        out.kind = Json::Kind::kNull;
        return literal("null");
      default:
        out.kind = Json::Kind::kNumber;
        return number(out.number);
    }
  }

  bool object(Json& out, std::size_t depth) {
    if (depth > kMaxJsonDepth) return fail("nested deeper than " + std::to_string(kMaxJsonDepth));
    out.kind = Json::Kind::kObject;
    ++i_;
    ws();
    if (eat('}')) return true;
    for (;;) {
      std::string key;
      if (peek() != '"') return fail("expected a field name");
      if (!string(key)) return false;
      ws();
      if (!eat(':')) return fail("expected ':'");
      ws();
      out.fields.push_back(JsonField{std::move(key), Json{}});
      if (!value(out.fields.back().value, depth)) return false;
      ws();
      if (eat('}')) return true;
      if (!eat(',')) return fail("expected ',' or '}'");
      ws();
    }
  }

  bool array(Json& out, std::size_t depth) {
    if (depth > kMaxJsonDepth) return fail("nested deeper than " + std::to_string(kMaxJsonDepth));
    out.kind = Json::Kind::kArray;
    ++i_;
    ws();
    if (eat(']')) return true;
    for (;;) {
      out.items.emplace_back();
      if (!value(out.items.back(), depth)) return false;
      ws();
      if (eat(']')) return true;
      if (!eat(',')) return fail("expected ',' or ']'");
      ws();
    }
  }

  static void utf8(std::string& out, std::uint32_t c) {
    if (c < 0x80) {
      out += static_cast<char>(c);
    } else if (c < 0x800) {
      out += static_cast<char>(0xC0 | (c >> 6));
      out += static_cast<char>(0x80 | (c & 0x3F));
    } else if (c < 0x10000) {
      out += static_cast<char>(0xE0 | (c >> 12));
      out += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (c & 0x3F));
    } else {
      out += static_cast<char>(0xF0 | (c >> 18));
      out += static_cast<char>(0x80 | ((c >> 12) & 0x3F));
      out += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (c & 0x3F));
    }
  }
  bool hex4(std::uint32_t& out) {
    if (i_ + 4 > s_.size()) return fail("bad \\u escape");
    out = 0;
    for (int k = 0; k < 4; ++k) {
      const char c = s_[i_++];
      out <<= 4;
      if (c >= '0' && c <= '9') {
        out |= static_cast<std::uint32_t>(c - '0');
      } else if (c >= 'a' && c <= 'f') {
        out |= static_cast<std::uint32_t>(c - 'a' + 10);
      } else if (c >= 'A' && c <= 'F') {
        out |= static_cast<std::uint32_t>(c - 'A' + 10);
      } else {
        return fail("bad \\u escape");
      }
    }
    return true;
  }

  bool string(std::string& out) {
    ++i_;  // the opening quote
    for (;;) {
      if (i_ >= s_.size()) return fail("unterminated string");
      const char c = s_[i_++];
      if (c == '"') return true;
      if (static_cast<unsigned char>(c) < 0x20) return fail("control character in a string");
      if (c != '\\') {
        out += c;
        continue;
      }
      if (i_ >= s_.size()) return fail("unterminated string");
      switch (s_[i_++]) {
        case '"':
          out += '"';
          break;
        case '\\':
          out += '\\';
          break;
        case '/':
          out += '/';
          break;
        case 'b':
          out += '\b';
          break;
        case 'f':
          out += '\f';
          break;
        case 'n':
          out += '\n';
          break;
        case 'r':
          out += '\r';
          break;
        case 't':
          out += '\t';
          break;
        case 'u': {
          std::uint32_t u = 0;
          if (!hex4(u)) return false;
          if (u >= 0xD800 && u < 0xDC00) {  // a UTF-16 surrogate pair (RFC 8259, 7)
            std::uint32_t low = 0;
            if (!eat('\\') || !eat('u') || !hex4(low) || low < 0xDC00 || low >= 0xE000)
              return fail("unpaired surrogate in a \\u escape");
            u = 0x10000 + ((u - 0xD800) << 10) + (low - 0xDC00);
          } else if (u >= 0xDC00 && u < 0xE000) {
            return fail("unpaired surrogate in a \\u escape");
          }
          utf8(out, u);
          break;
        }
        default:
          return fail("bad escape in a string");
      }
    }
  }

  // RFC 8259's number grammar: -? (0 | [1-9][0-9]*) (. [0-9]+)? ([eE] [+-]? [0-9]+)?
  bool number(double& out) {
    const std::size_t start = i_;
    const auto digits = [&] {
      const std::size_t from = i_;
      while (i_ < s_.size() && s_[i_] >= '0' && s_[i_] <= '9')
        ++i_;
      return i_ > from;
    };
    eat('-');
    if (eat('0')) {
    } else if (!digits()) {
      return fail("expected a value");
    }
    if (eat('.') && !digits()) return fail("bad number");
    if (eat('e') || eat('E')) {
      if (!eat('+')) eat('-');
      if (!digits()) return fail("bad number");
    }
    if (i_ - start > 64) return fail("number longer than 64 characters");
    const std::string text(s_.substr(start, i_ - start));
    out = std::strtod(text.c_str(), nullptr);
    if (!std::isfinite(out)) return fail("number out of range");
    return true;
  }

  std::string_view s_;
  std::size_t i_ = 0;
  std::size_t values_ = 0;
  std::string error_;
};

}  // namespace

const Json* Json::get(std::string_view key) const {
  for (const JsonField& f : fields)
    if (f.key == key) return &f.value;
  return nullptr;
}

std::variant<Json, std::string> parse_json(std::string_view text) {
  Json out;
  Parser parser(text);
  if (std::string error = parser.parse(out); !error.empty()) return error;
  return out;
}

}  // namespace rigid::view
