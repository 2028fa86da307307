// rigidctl: pokes a running rigidd by hand. Wiring only: ctl_options (command line), ctl_run (the
// commands).
#include <signal.h>

#include <exception>
#include <iostream>
#include <string_view>
#include <vector>

#include "ctl/ctl_options.hpp"
#include "ctl/ctl_run.hpp"
#include "util/signal_watcher.hpp"

int main(int argc, char** argv) {
  using namespace rigid;
  const std::vector<std::string_view> args(argv + 1, argv + argc);
  ctl::CtlOptions options;
  try {
    options = ctl::parse_options(args);
  } catch (const clients::UsageError& e) {
    std::cerr << "rigidctl: " << e.what() << '\n';
    return clients::kExitUsage;
  }
  if (options.help) {
    std::cout << ctl::usage();
    return clients::kExitOk;
  }
  try {
    // Before the bus starts its threads: they inherit the blocked signals.
    util::SignalWatcher signals({SIGINT, SIGTERM});
    return ctl::run(options, signals, std::cout, std::cerr);
  } catch (const std::exception& e) {
    std::cerr << "rigidctl: " << e.what() << '\n';
    return clients::kExitFailed;
  }
}
