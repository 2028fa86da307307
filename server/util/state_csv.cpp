// CSV rows of body states.
#include "util/state_csv.hpp"

#include <array>
#include <charconv>

namespace rigid::util {

void append_number(std::string& out, double x) {
  std::array<char, 32> buf{};
  const auto r =
      std::to_chars(buf.data(), buf.data() + buf.size(), x, std::chars_format::general, 17);
  out.append(buf.data(), r.ptr);
}

void append_state_row(std::string& out, double t, std::string_view body,
                      const std::array<double, 13>& values) {
  append_number(out, t);
  out += ',';
  // Body names are restricted by the scene loader to characters that need no CSV quoting.
  out += body;
  for (double v : values) {
    out += ',';
    append_number(out, v);
  }
  out += '\n';
}

}  // namespace rigid::util
