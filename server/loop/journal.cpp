#include "loop/journal.hpp"

#include <chrono>
#include <variant>

#include "common/log_records.hpp"
#include "loop/clock.hpp"
#include "util/thread_name.hpp"

namespace rigid::loop {

Journal::Journal(const Options& options, const msgs::LogHeader& header, Log& log,
                 CommandSink on_command)
    : log_(log),
      on_command_(std::move(on_command)),
      path_(options.path),
      queue_(options.capacity),
      start_ns_(monotonic_ns()) {
  if (path_.empty()) return;
  file_ = std::make_unique<common::RecordWriter>(path_, /*overwrite=*/false);
  *record_.mutable_header() = header;
  append(record_);
  file_->flush();
}

Journal::~Journal() {
  stop();
}

void Journal::start() {
  if (thread_.joinable()) return;
  thread_ = std::thread([this] { run(); });
  util::name_thread(thread_, "rigid-journal");
}

void Journal::stop() {
  if (thread_.joinable()) {
    stop_.store(true, std::memory_order_release);
    thread_.join();
  }
  drain();  // what came after the thread's last pass (or everything, if it never started)
  close_file();
}

void Journal::run() {
  while (!stop_.load(std::memory_order_acquire)) {
    std::this_thread::sleep_for(std::chrono::milliseconds(kPollMs));
    drain();
  }
}

void Journal::drain() {
  // Checked before popping: a loss seen now may come after entries still queued, so the gap is
  // recorded a little early rather than late (a replay then stops before, never after, it).
  const std::int64_t dropped = dropped_.load(std::memory_order_relaxed);
  if (dropped > gaps_seen_) {
    log_.line("journal: " + std::to_string(dropped - gaps_seen_) +
              " entries lost (the writer fell behind the loop); " + std::to_string(dropped) +
              " since start: a replay stops at the first loss");
    gaps_seen_ = dropped;
    gap_pending_ = true;
  }
  common::JournalEntry entry;
  while (queue_.try_pop(entry))
    write(entry);
  if (file_) {
    try {
      file_->flush();
    } catch (const common::LogFileError& e) {
      log_.line(std::string("journal: ") + e.what() + "; the journal stops here");
      file_.reset();
    }
  }
}

void Journal::write(const common::JournalEntry& entry) {
  if (gap_pending_) {
    msgs::JournalGap* gap = record_.mutable_gap();
    gap->set_dropped(gaps_seen_);
    gap->set_tick(entry.tick);
    append(record_);
    gap_pending_ = false;
  }
  last_tick_ = entry.tick;
  if (const auto* published = std::get_if<common::PublishedHash>(&entry.what)) {
    msgs::StateHash* hash = record_.mutable_state_hash();
    hash->set_tick(entry.tick);
    hash->set_hash(published->hash);
    append(record_);
    return;
  }
  if (const auto* contacts = std::get_if<common::ContactsHash>(&entry.what)) {
    msgs::ContactHash* hash = record_.mutable_contact_hash();
    hash->set_tick(entry.tick);
    hash->set_hash(contacts->hash);
    hash->set_events(contacts->events);
    append(record_);
    return;
  }
  const rigid::AcceptedCommand accepted = common::accepted_command(entry);
  if (on_command_) on_command_(accepted);
  if (file_) {
    common::to_record(accepted, monotonic_ns() - start_ns_, *record_.mutable_command());
    append(record_);
  }
}

void Journal::append(const msgs::LogRecord& record) {
  if (!file_) return;
  try {
    file_->append(record);
    records_.store(file_->records(), std::memory_order_relaxed);
  } catch (const common::LogFileError& e) {
    log_.line(std::string("journal: ") + e.what() + "; the journal stops here");
    file_.reset();
  }
}

void Journal::close_file() {
  if (!file_) return;
  if (gap_pending_) {
    msgs::JournalGap* gap = record_.mutable_gap();
    gap->set_dropped(gaps_seen_);
    gap->set_tick(last_tick_);
    append(record_);
    gap_pending_ = false;
  }
  msgs::LogEnd* end = record_.mutable_end();
  end->set_records(file_ ? file_->records() : 0);
  end->set_dropped(dropped());
  end->set_end_unix_ns(realtime_ns());
  append(record_);
  if (!file_) return;
  try {
    file_->close();
    log_.line("journal: " + path_ + ": " + std::to_string(file_->records()) + " records, " +
              std::to_string(dropped()) + " entries lost");
  } catch (const common::LogFileError& e) {
    log_.line(std::string("journal: ") + e.what());
  }
  file_.reset();
}

}  // namespace rigid::loop
