#include "record/recorder.hpp"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <mutex>
#include <optional>
#include <ostream>
#include <utility>

#include "cli/dds_log.hpp"
#include "common/log_records.hpp"
#include "common/record_file.hpp"
#include "record/decimation.hpp"
#include "rigid/client/names.hpp"
#include "rigid/client/session.hpp"
#include "transport/lcm/lcm_transport.hpp"

namespace rigid::record {
namespace {

using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

std::int64_t unix_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

// Records from the transport's thread to the writer, with what they are, for the live line.
class RecordQueue {
 public:
  // The recording starts now: what came before (while waiting for the scene) is dropped.
  void start() {
    const std::lock_guard lock(mutex_);
    start_ = Clock::now();
    started_ = true;
    queue_.clear();
    queued_bytes_ = 0;
  }

  template <class Fill>
  void push(Fill fill) {
    Clock::time_point start;
    {
      const std::lock_guard lock(mutex_);
      if (!started_) return;
      start = start_;
    }
    msgs::LogRecord record;
    fill(record,
         std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - start).count());
    const std::size_t bytes = record.ByteSizeLong();
    const std::lock_guard lock(mutex_);
    if (queued_bytes_ + bytes > kMaxQueuedBytes) {
      ++dropped_;
      return;
    }
    queued_bytes_ += bytes;
    queue_.push_back(std::move(record));
  }

  std::deque<msgs::LogRecord> take() {
    const std::lock_guard lock(mutex_);
    queued_bytes_ = 0;
    return std::exchange(queue_, {});
  }
  std::int64_t dropped() const {
    const std::lock_guard lock(mutex_);
    return dropped_;
  }

 private:
  mutable std::mutex mutex_;
  Clock::time_point start_;
  bool started_ = false;
  std::deque<msgs::LogRecord> queue_;
  std::size_t queued_bytes_ = 0;
  std::int64_t dropped_ = 0;
};

struct Counts {
  std::int64_t states = 0, scenes = 0, stats = 0, commands = 0, contacts = 0;
  std::int64_t decimated = 0;  // states left out by --every
  void count(const msgs::LogRecord& r) {
    states += r.has_state();
    scenes += r.has_scene();
    stats += r.has_stats();
    commands += r.has_command();
    contacts += r.has_contacts() ? r.contacts().kinds_size() : 0;
  }
};

std::string live_line(const std::string& path, double seconds, const Counts& c,
                      const common::RecordWriter& file, std::int64_t dropped) {
  char buffer[512];
  std::snprintf(buffer, sizeof buffer,
                "%s: %.1f s, %lld states, %lld commands, %lld stats, %lld scenes, %.2f MB",
                path.c_str(), seconds, static_cast<long long>(c.states),
                static_cast<long long>(c.commands), static_cast<long long>(c.stats),
                static_cast<long long>(c.scenes), static_cast<double>(file.bytes()) / 1e6);
  std::string line = buffer;
  if (file.record_bytes() + common::kLogPreambleBytes > file.bytes()) {
    std::snprintf(buffer, sizeof buffer, " (%.2f MB of records)",
                  static_cast<double>(file.record_bytes()) / 1e6);
    line += buffer;
  }
  if (c.contacts > 0) line += ", " + std::to_string(c.contacts) + " contact events";
  if (c.decimated > 0) line += ", " + std::to_string(c.decimated) + " states left out (--every)";
  if (dropped > 0) line += ", " + std::to_string(dropped) + " dropped (the disk is too slow)";
  return line;
}

msgs::LogHeader header(const RecordOptions& o, const rigid::SceneDescription& scene) {
  msgs::LogHeader h;
  h.set_kind(msgs::LogHeader::RECORDING);
  h.set_schema_version(common::kLogSchemaVersion);
  h.set_software_version(common::software_version());
  h.set_writer("rigid-record");
  h.set_start_unix_ns(unix_ns());
  common::to_record(scene, 0, *h.mutable_scene());
  h.set_integrator(scene.integrator);
  h.set_rate_hz(scene.dt > 0 ? 1.0 / scene.dt : 0.0);
  const bool dds = o.bus.bus == rigid::Bus::kDds;
  h.set_transport(dds ? "dds" : "lcm");
  h.set_prefix(o.bus.prefix);
  h.set_address(
      dds ? "domain " + std::to_string(o.bus.dds_domain)
          : (o.bus.lcm_url.empty() ? std::string(transport::lcm::kDefaultUrl) : o.bus.lcm_url));
  return h;
}

}  // namespace

int record(const RecordOptions& o, util::SignalWatcher& signals, std::ostream& err) {
  const clients::DdsLog dds_log;  // before the bus: Cyclone's lines are told in our words
  // The file first: a name that cannot be used fails at once, not after the wait for rigidd.
  std::optional<common::RecordWriter> file;
  try {
    common::Compression compression;
    compression.zstd = o.compress;
    compression.level = kZstdLevel;
    file.emplace(o.file, o.force, compression);
  } catch (const common::FileExistsError&) {
    err << "rigid-record: " << o.file << " already exists (--force overwrites it)\n";
    return clients::kExitFailed;
  } catch (const common::LogFileError& e) {
    err << "rigid-record: " << e.what() << '\n';
    return clients::kExitFailed;
  }
  Decimation decimation(o.every);
  std::atomic<std::int64_t> decimated{0};
  RecordQueue queue;
  std::optional<rigid::SceneDescription> last_scene;
  std::mutex scene_mutex;
  std::unique_ptr<client::Session> session;
  try {
    session = std::make_unique<client::Session>(o.bus);
  } catch (const client::BusError& e) {
    err << "rigid-record: " << clients::bus_error_line(e.what(), o.bus, dds_log) << '\n';
    file.reset();
    std::filesystem::remove(o.file);
    return clients::kExitFailed;
  }
  session->on_each_state([&](const rigid::StateFrame& s) {
    if (!decimation.keep(s.tick)) {
      decimated.fetch_add(1, std::memory_order_relaxed);
      return;
    }
    queue.push(
        [&](msgs::LogRecord& r, std::int64_t t) { common::to_record(s, t, *r.mutable_state()); });
  });
  session->on_each_stats([&](const rigid::StatsReport& s) {
    queue.push(
        [&](msgs::LogRecord& r, std::int64_t t) { common::to_record(s, t, *r.mutable_stats()); });
  });
  session->on_each_accepted([&](const rigid::AcceptedCommand& a) {
    queue.push(
        [&](msgs::LogRecord& r, std::int64_t t) { common::to_record(a, t, *r.mutable_command()); });
  });
  // Every tick's contact events, whatever --every keeps of the states (an impact is not repeated).
  session->on_each_contacts([&](const rigid::ContactEvents& c) {
    queue.push([&](msgs::LogRecord& r, std::int64_t t) {
      common::to_record(c, t, *r.mutable_contacts());
    });
  });
  session->on_each_scene([&](const rigid::SceneDescription& s) {
    // LCM repeats the scene every second: keep it only when it changes.
    {
      const std::lock_guard lock(scene_mutex);
      if (last_scene && *last_scene == s) return;
      last_scene = s;
    }
    decimation.scene(s);
    queue.push(
        [&](msgs::LogRecord& r, std::int64_t t) { common::to_record(s, t, *r.mutable_scene()); });
  });

  const auto scene = session->wait_scene(o.timeout);
  if (!scene) {
    err << "rigid-record: no SceneInfo from rigidd within "
        << static_cast<double>(o.timeout.count()) / 1000.0 << " s on " << client::describe(o.bus)
        << clients::no_rigidd_hint(o.bus, dds_log) << "; " << o.file << " not written\n";
    session.reset();
    file.reset();
    std::filesystem::remove(o.file);
    return clients::kExitTimeout;
  }

  const bool tty = ::isatty(STDERR_FILENO) == 1;
  Counts counts;
  decimation.scene(*scene);
  queue.start();
  decimated.store(0, std::memory_order_relaxed);
  const auto start = Clock::now();
  auto next_line = start;
  const auto line_period = tty ? 500ms : 5000ms;
  const auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };
  // How long it recorded: until it stopped listening, not until the bus is torn down and the file
  // closed (which under a sanitizer took 0.1 s and made a 2 s recording say 2.1 s).
  double recorded_for = 0;
  try {
    msgs::LogRecord head;
    *head.mutable_header() = header(o, *scene);
    file->append(head);
    for (;;) {
      // No later than the duration's end, so that it stops on time.
      auto wait = std::chrono::duration_cast<std::chrono::milliseconds>(kFlushPeriod);
      if (o.duration) {
        const double left_ms = (*o.duration - elapsed()) * 1e3;
        wait = std::min(wait, std::chrono::milliseconds(
                                  static_cast<std::int64_t>(std::ceil(std::max(left_ms, 0.0)))));
      }
      const std::optional<int> signal = signals.wait(wait);
      const bool done = signal || (o.duration && elapsed() >= *o.duration);
      if (done) {
        recorded_for = elapsed();
        session.reset();  // no more messages: what is queued is all there is
      }
      for (const msgs::LogRecord& r : queue.take()) {
        file->append(r);
        counts.count(r);
      }
      file->flush();
      counts.decimated = decimated.load(std::memory_order_relaxed);
      if (done) break;
      if (Clock::now() >= next_line) {
        err << (tty ? "\r" : "") << "recording "
            << live_line(o.file, elapsed(), counts, *file, queue.dropped())
            << (tty ? "\x1b[K" : "\n");
        err.flush();
        next_line = Clock::now() + line_period;
      }
    }
    msgs::LogRecord end;
    end.mutable_end()->set_records(file->records());
    end.mutable_end()->set_dropped(queue.dropped());
    end.mutable_end()->set_end_unix_ns(unix_ns());
    file->append(end);
    file->close();
  } catch (const common::DiskFullError& e) {
    // What went out whole stays: the writer cut the file back to its last complete frame.
    const double seconds = recorded_for > 0 ? recorded_for : elapsed();
    session.reset();
    char when[64];
    std::snprintf(when, sizeof when, "%.1f s", seconds);
    err << (tty ? "\n" : "") << "rigid-record: " << e.what() << ": recording stopped after " << when
        << "; " << o.file << " holds the " << file->records_written()
        << " records written before (readable, without its closing record)\n";
    return clients::kExitFailed;
  } catch (const common::LogFileError& e) {
    err << (tty ? "\n" : "") << "rigid-record: " << e.what() << '\n';
    return clients::kExitFailed;
  }
  err << (tty ? "\r" : "") << "recorded "
      << live_line(o.file, recorded_for, counts, *file, queue.dropped())
      << (tty ? "\x1b[K\n" : "\n");
  return clients::kExitOk;
}

}  // namespace rigid::record
