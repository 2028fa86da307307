#include "record/record_options.hpp"

#include <array>
#include <vector>

namespace rigid::record {
namespace {

using clients::quoted;
using clients::UsageError;

constexpr std::array<std::string_view, 4> kFlags{"--help", "-h", "--force", "-f"};

bool takes(Command c, std::string_view option, bool bus_option) {
  switch (c) {
    case Command::kRecord:
      return bus_option || option == "--duration" || option == "--force" || option == "-f" ||
             option == "--timeout" || option == "--every" || option == "--compress";
    case Command::kInfo:
      return false;
    case Command::kExport:
      return option == "--csv" || option == "--mcap" || option == "--prefix" ||
             option == "--force" || option == "-f" || option == "--compress";
    case Command::kPlay:
      return bus_option || option == "--speed";
  }
  return false;
}

}  // namespace

RecordOptions parse_options(std::span<const std::string_view> args) {
  RecordOptions o;
  clients::ArgReader reader(args, kFlags);
  std::optional<Command> command;
  std::string_view command_name;
  std::vector<std::string_view> positional;
  std::vector<clients::ArgReader::Arg> options;
  while (const auto arg = reader.next()) {
    if (arg->name == "--help" || arg->name == "-h") {
      o.help = true;
    } else if (!arg->name.empty()) {
      options.push_back(*arg);
    } else if (command) {
      positional.push_back(arg->value);
    } else {
      command_name = arg->value;
      if (arg->value == "record") {
        command = Command::kRecord;
      } else if (arg->value == "info") {
        command = Command::kInfo;
      } else if (arg->value == "export") {
        command = Command::kExport;
      } else if (arg->value == "play") {
        command = Command::kPlay;
      } else {
        throw UsageError("unknown command " + quoted(arg->value) +
                         " (commands: record, info, export, play)");
      }
    }
  }
  if (o.help) return o;
  if (!command) throw UsageError("missing the command (record, info, export, play; see --help)");
  o.command = *command;
  for (const auto& arg : options) {
    client::BusOptions probe;
    const bool bus_option = clients::parse_bus_option(arg, probe);
    if (!takes(o.command, arg.name, bus_option)) {
      throw UsageError("unknown option " + quoted(arg.name) + " for " + std::string(command_name) +
                       " (see --help)");
    }
    if (arg.name == "--prefix") o.bus_prefix_given = true;
    if (clients::parse_bus_option(arg, o.bus)) continue;
    if (arg.name == "--duration") {
      o.duration = clients::parse_positive(arg.name, arg.value, "a duration in seconds > 0");
    } else if (arg.name == "--force" || arg.name == "-f") {
      o.force = true;
    } else if (arg.name == "--every") {
      o.every = clients::parse_count(arg.name, arg.value);
    } else if (arg.name == "--compress") {
      if (arg.value == "zstd") {
        o.compress = true;
      } else if (arg.value == "none") {
        o.compress = false;
      } else {
        throw UsageError("--compress: expected zstd or none, got " + quoted(arg.value));
      }
    } else if (arg.name == "--timeout") {
      o.timeout = clients::parse_seconds(arg.name, arg.value);
    } else if (arg.name == "--csv") {
      if (arg.value.empty()) throw UsageError("--csv: expected a file name, got ''");
      o.csv = std::string(arg.value);
    } else if (arg.name == "--mcap") {
      if (arg.value.empty()) throw UsageError("--mcap: expected a file name, got ''");
      o.mcap = std::string(arg.value);
    } else if (arg.name == "--speed") {
      o.speed = clients::parse_positive(arg.name, arg.value, "a speed factor > 0");
    }
  }
  const char* what = o.command == Command::kRecord ? "the output file" : "the input file";
  if (positional.empty()) {
    throw UsageError(std::string(command_name) + ": missing " + what + " (see --help)");
  }
  if (positional.size() > 1) {
    throw UsageError(std::string(command_name) + ": unexpected argument " + quoted(positional[1]));
  }
  o.file = std::string(positional[0]);
  if (o.command == Command::kExport && o.csv.empty() && o.mcap.empty()) {
    throw UsageError("export: missing --csv OUT or --mcap OUT");
  }
  if (!o.csv.empty() && o.csv == o.mcap) {
    throw UsageError("export: --csv and --mcap name the same file " + quoted(o.csv));
  }
  return o;
}

std::string usage() {
  std::string text =
      R"(Usage: rigid-record record OUT [--duration S] [--every N] [--compress zstd|none] [--force]
                          [--timeout S] [BUS OPTIONS]
       rigid-record info FILE
       rigid-record export FILE [--csv OUT] [--mcap OUT] [--compress zstd|none] [--force]
                           [--prefix P]
       rigid-record play FILE [--speed X] [BUS OPTIONS]

Records what rigidd publishes on one bus, and reads recordings back.

  record OUT      subscribe and write rigidd's states, scene, stats and accepted commands to OUT,
                  one file of framed Protobuf records (msgs/rigid.proto, "Log records"), until
                  --duration S has passed or SIGINT/SIGTERM. Written as it goes: a recorder
                  killed at any instant leaves OUT readable up to its last complete record.
                  An existing OUT is refused unless --force. A live line on stderr shows what
                  has been written. A full disk ends the recording with exit status 1 and OUT
                  readable up to the last record that fitted
    --every N     keep one state in N: those whose tick is a multiple of N times the scene's
                  publish_every (the scene, Stats and commands are all kept)
    --compress C  zstd (default): records in zstd-compressed chunks (log format 2); none:
                  as they are (format 1, which readers older than format 2 read too)
  info FILE       what FILE holds: its header (scene, integrator, rate, versions), how many
                  records of each kind, the time span, and whether it ends cleanly or in a
                  damaged tail (reported, not an error). Journals (rigidd --journal) too
  export FILE     the states as CSV (rigid-sim's columns: t,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,
    --csv OUT     wx,wy,wz; a row per body per state). FILE may also be an lcm-logger log of
                  rigidd's channels; --prefix P picks P_RIGID_STATE there
    --mcap OUT    and/or an MCAP file for Foxglove, its chunks zstd-compressed (--compress
                  none: uncompressed)
  play FILE       republish FILE's scene and states at the pace they were recorded (--speed X:
                  X times faster) on the bus, as rigidd would: run it without a rigidd on the
                  same bus and prefix

Bus options (record, play):
)";
  text += clients::bus_options_help();
  text += R"(  --timeout S        record: how long to wait for rigidd's SceneInfo (default 5)

Exit status: 0 done, 1 a file or bus error, 2 a bad command line, 3 no rigidd answered.
)";
  return text;
}

}  // namespace rigid::record
