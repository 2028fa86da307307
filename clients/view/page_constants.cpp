// rigid_view_page_constants OUT.js: writes the page's protocol_constants.js, the numbers of
// protocol.hpp that the page's decoder and commands use, taken from the compiled constants
// themselves (no parsing of the header), so that the page and rigid-view cannot disagree on a
// frame's layout or a limit. Run by the build (clients/view/CMakeLists.txt); the frames rigid-view
// encodes are decoded with them in tests/view/protocol_test.mjs.
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <string_view>

#include "protocol.hpp"

namespace {

using namespace rigid::view;

// A JavaScript string literal (JSON's quoting, which JavaScript reads the same).
std::string quoted(std::string_view s) {
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    if (static_cast<unsigned char>(c) < 0x20) {
      char b[8];
      std::snprintf(b, sizeof b, "\\u%04x", static_cast<unsigned>(c));
      out += b;
      continue;
    }
    out += c;
  }
  return out + '"';
}

std::string number(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

std::string page_constants() {
  std::ostringstream js;
  const auto line = [&js](std::string_view name, const std::string& value) {
    js << "export const " << name << " = " << value << ";\n";
  };
  const auto integer = [&line](std::string_view name, std::uint64_t v) {
    line(name, std::to_string(v));
  };
  js << "// Generated from clients/view/protocol.hpp by rigid_view_page_constants "
        "(page_constants.cpp)\n"
        "// when rigid-view is built: protocol.hpp says what each one means. Not to be edited.\n";
  char magic[16];
  std::snprintf(magic, sizeof magic, "0x%08x", static_cast<unsigned>(kStateMagic));
  line("kStateMagic", magic);
  integer("kStateHeaderBytes", kStateHeaderBytes);
  integer("kStateBodiesAt", kStateBodiesAt);
  integer("kStateGenerationAt", kStateGenerationAt);
  integer("kStateFlagsAt", kStateFlagsAt);
  integer("kStateTickAt", kStateTickAt);
  integer("kStateSimTimeAt", kStateSimTimeAt);
  integer("kStateStampAt", kStateStampAt);
  integer("kStateFloat32", kStateFloat32);
  integer("kStatePoses", kStatePoses);
  integer("kPoseBytesPerBody", kPoseBytesPerBody);
  integer("kPoseTrailerBytes", kPoseTrailerBytes);
  integer("kPoseWorstEnergyAt", kPoseWorstEnergyAt);
  integer("kPoseWorstEnergySlotAt", kPoseWorstEnergySlotAt);
  integer("kPoseWorstMomentumAt", kPoseWorstMomentumAt);
  integer("kPoseWorstMomentumSlotAt", kPoseWorstMomentumSlotAt);
  integer("kPoseWatchedCountAt", kPoseWatchedCountAt);
  integer("kWatchedRecordBytes", kWatchedRecordBytes);
  integer("kWatchedEnergyAt", kWatchedEnergyAt);
  integer("kWatchedMomentumAt", kWatchedMomentumAt);
  integer("kWatchedStateAt", kWatchedStateAt);
  integer("kMaxWrenchesShown", kMaxWrenchesShown);
  integer("kMaxSteps", static_cast<std::uint64_t>(kMaxSteps));
  line("kWatchLifetime", number(kWatchLifetime));
  line("kAckCommand", quoted(kAckCommand));
  return js.str();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: rigid_view_page_constants OUT.js\n");
    return 2;
  }
  const std::string text = page_constants();
  std::ofstream out(argv[1], std::ios::binary | std::ios::trunc);
  if (!(out << text) || !out.flush()) {
    std::fprintf(stderr, "rigid_view_page_constants: cannot write %s\n", argv[1]);
    return 1;
  }
  return 0;
}
