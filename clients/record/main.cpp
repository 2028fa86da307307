// rigid-record: records what rigidd publishes, and reads recordings back (info, export, play).
// Wiring only: record_options (command line), recorder, log_info, export_csv, export_mcap,
// player.
#include <signal.h>

#include <exception>
#include <iostream>
#include <string_view>
#include <vector>

#include "record/export_csv.hpp"
#include "record/export_mcap.hpp"
#include "record/log_info.hpp"
#include "record/player.hpp"
#include "record/record_options.hpp"
#include "record/recorder.hpp"
#include "util/signal_watcher.hpp"

int main(int argc, char** argv) {
  using namespace rigid;
  const std::vector<std::string_view> args(argv + 1, argv + argc);
  record::RecordOptions options;
  try {
    options = record::parse_options(args);
  } catch (const clients::UsageError& e) {
    std::cerr << "rigid-record: " << e.what() << '\n';
    return clients::kExitUsage;
  }
  if (options.help) {
    std::cout << record::usage();
    return clients::kExitOk;
  }
  try {
    switch (options.command) {
      case record::Command::kInfo:
        return record::info(options.file, std::cout, std::cerr);
      case record::Command::kExport: {
        int status = options.csv.empty() ? clients::kExitOk
                                         : record::export_csv(options, std::cout, std::cerr);
        if (status == clients::kExitOk && !options.mcap.empty()) {
          status = record::export_mcap(options, std::cout, std::cerr);
        }
        return status;
      }
      case record::Command::kRecord:
      case record::Command::kPlay: {
        // Before the bus starts its threads: they inherit the blocked signals.
        util::SignalWatcher signals({SIGINT, SIGTERM});
        return options.command == record::Command::kRecord
                   ? record::record(options, signals, std::cerr)
                   : record::play(options, signals, std::cerr);
      }
    }
  } catch (const std::exception& e) {
    std::cerr << "rigid-record: " << e.what() << '\n';
  }
  return clients::kExitFailed;
}
