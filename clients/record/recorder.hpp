// rigid-record record: subscribes to rigidd on one bus and writes its scene, states, stats and
// accepted commands to a log file (common/record_file.hpp) as they arrive.
//
// The transport's thread turns each message into a record (or drops a state --every leaves out)
// and queues it (bounded: past
// kMaxQueuedBytes the newest are dropped and counted, so a stalled disk cannot eat the memory);
// the main thread writes the queue out and hands it to the kernel every kFlushPeriod, so a
// recorder killed at any instant loses at most that much, and never what came before.
#pragma once

#include <chrono>
#include <iosfwd>

#include "record/record_options.hpp"
#include "util/signal_watcher.hpp"

namespace rigid::record {

inline constexpr std::chrono::milliseconds kFlushPeriod{100};
inline constexpr std::size_t kMaxQueuedBytes = 256u << 20;
// zstd's level for --compress zstd: bench/notes/recording.md measures the levels' ratio and CPU.
inline constexpr int kZstdLevel = 3;

// Returns the exit status; the live line and the closing summary go to `err`.
int record(const RecordOptions& options, util::SignalWatcher& signals, std::ostream& err);

}  // namespace rigid::record
