// rigid-view's command line: the bus options (as rigidctl takes them), --listen, --read-only,
// --web-dir, --foxglove-origin, and FILE: a recording to play instead of the bus (only --prefix of
// the bus options applies then: it picks an lcm-logger log's channels).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "cli/cli.hpp"

namespace rigid::view {

struct ViewOptions {
  client::BusOptions bus;
  std::string host = "127.0.0.1";  // as given: a host name or an address (IPv6 without brackets)
  std::uint16_t port = 8765;       // 0: any free port (printed)
  bool read_only = false;
  std::string web_dir;  // empty: "web" next to the executable
  std::string file;     // rigid-view FILE: play this recording; empty: live from the bus
  bool prefix_given = false;
  std::int64_t max_memory_mib = 512;  // FILE: the most its states may take in memory
  // --foxglove-origin (repeatable): more origins whose Foxglove clients may connect.
  std::vector<std::string> foxglove_origins;
  bool help = false;
};

// Throws clients::UsageError (one line).
ViewOptions parse_options(std::span<const std::string_view> args);
std::string usage();
// The host as a URL spells it: an IPv6 address between brackets.
std::string url_host(const std::string& host);

}  // namespace rigid::view
