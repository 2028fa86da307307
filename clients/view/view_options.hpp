// rigid-view's command line: the bus options (as rigidctl takes them), --listen, --read-only,
// --web-dir.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "common/cli.hpp"

namespace rigid::view {

struct ViewOptions {
  client::BusOptions bus;
  std::string host = "127.0.0.1";
  std::uint16_t port = 8765;  // 0: any free port (printed)
  bool read_only = false;
  std::string web_dir;  // empty: "web" next to the executable
  bool help = false;
};

// Throws clients::UsageError (one line).
ViewOptions parse_options(std::span<const std::string_view> args);
std::string usage();
// Whether the address is reachable from other hosts (not loopback).
bool listens_beyond_host(const std::string& host);

}  // namespace rigid::view
