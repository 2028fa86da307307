// rigid-record play: republishes a recording's scene and states on a bus at the pace they were
// recorded (scaled by --speed), as rigidd would publish them: subscribers, rigidctl echo and
// controllers cannot tell the difference (the states carry the recorded ticks; their stamp is the
// time of republishing).
#pragma once

#include <iosfwd>

#include "record/record_options.hpp"
#include "util/signal_watcher.hpp"

namespace rigid::record {

int play(const RecordOptions& options, util::SignalWatcher& signals, std::ostream& err);

}  // namespace rigid::record
