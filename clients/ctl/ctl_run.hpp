// rigidctl's commands against a running rigidd. Each prints what it got to `out` (errors: one line
// on `err`) and returns the exit status (cli/cli.hpp: 0, 1 refused or no bus, 3 no answer).
#pragma once

#include <iosfwd>

#include "ctl/ctl_options.hpp"
#include "util/signal_watcher.hpp"

namespace rigid::ctl {

// `signals` (SIGINT, SIGTERM) end echo and stats; it must exist before any thread starts.
int run(const CtlOptions& options, util::SignalWatcher& signals, std::ostream& out,
        std::ostream& err);

}  // namespace rigid::ctl
