// Where the loop's journal entries (journal_entry.hpp) leave the loop thread. The loop pushes each
// entry into a bounded queue: no I/O, no allocation, no system call, never a wait (a full queue
// drops the entry and counts it). The journal's own thread polls the queue every few milliseconds,
// writes the entries to the journal file when there is one (rigidd --journal; record_file.hpp
// framing, a JOURNAL LogHeader first, a LogEnd when it closes) and hands each accepted command to
// `on_command` (the server publishes it on rigid/accepted).
//
// A lost entry breaks a replay from that point on: the writer records a JournalGap where it noticed
// the loss (so a replay stops there instead of reporting a false divergence) and logs it. A file
// that can no longer be written (disk full) is logged once and closed; commands still go out.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <thread>

#include "common/journal_entry.hpp"
#include "common/record_file.hpp"
#include "loop/bounded_queue.hpp"
#include "loop/log.hpp"
#include "rigid.pb.h"

namespace rigid::loop {

class Journal {
 public:
  struct Options {
    std::string path;  // the journal file; empty: none (accepted commands still go to on_command)
    // Entries in flight. The writer drains it every kPollMs, so this holds ~1.6 s of a loop that
    // journals 10^4 entries a second.
    std::size_t capacity = 16384;
  };
  using CommandSink = std::function<void(const rigid::AcceptedCommand&)>;

  // Creates the file and writes `header` (throws LogFileError, one line naming the file).
  Journal(const Options& options, const msgs::LogHeader& header, Log& log, CommandSink on_command);
  ~Journal();
  Journal(const Journal&) = delete;
  Journal& operator=(const Journal&) = delete;

  void start();
  // Writes what is queued, the closing LogEnd, and closes the file. Idempotent.
  void stop();

  // Loop thread.
  void push(const common::JournalEntry& entry) {
    if (!queue_.try_push(entry)) dropped_.fetch_add(1, std::memory_order_relaxed);
  }

  bool has_file() const { return file_ != nullptr; }
  const std::string& path() const { return path_; }
  std::int64_t dropped() const { return dropped_.load(std::memory_order_relaxed); }
  std::int64_t records() const { return records_.load(std::memory_order_relaxed); }

  static constexpr int kPollMs = 5;

 private:
  void run();
  void drain();
  void write(const common::JournalEntry& entry);
  void append(const msgs::LogRecord& record);
  void close_file();

  Log& log_;
  CommandSink on_command_;
  std::string path_;
  std::unique_ptr<common::RecordWriter> file_;  // writer thread only, after start()
  BoundedQueue<common::JournalEntry> queue_;
  std::int64_t start_ns_ = 0;
  std::int64_t gaps_seen_ = 0;  // drops already recorded as a gap (writer thread)
  bool gap_pending_ = false;    // a loss noticed, its gap not written yet (writer thread)
  std::int64_t last_tick_ = 0;  // of the last entry written (writer thread)
  msgs::LogRecord record_;      // reused (writer thread)
  std::atomic<std::int64_t> dropped_{0};
  std::atomic<std::int64_t> records_{0};
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace rigid::loop
