// rigid-record's command line (every error is one line naming the argument and its value; the
// program then exits with status 2).
#pragma once

#include <chrono>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "cli/cli.hpp"

namespace rigid::record {

enum class Command { kRecord, kInfo, kExport, kPlay };

struct RecordOptions {
  Command command = Command::kRecord;
  std::string file;  // record: the output; info, export, play: the input
  client::BusOptions bus;
  bool bus_prefix_given = false;            // export: --prefix picks an LCM log's channels
  std::chrono::milliseconds timeout{5000};  // record: for rigidd's SceneInfo
  std::optional<double> duration;           // record: seconds; unset: until SIGINT/SIGTERM
  bool force = false;                       // record, export: overwrite OUT
  std::int64_t every = 1;                   // record: keep the states of every Nth publication
  bool compress = true;  // record: zstd chunks (format 2); export: zstd MCAP chunks
  std::string csv;       // export
  std::string mcap;      // export
  double speed = 1.0;    // play
  bool help = false;
};

RecordOptions parse_options(std::span<const std::string_view> args);

std::string usage();

}  // namespace rigid::record
