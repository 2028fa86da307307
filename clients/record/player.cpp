#include "record/player.hpp"

#include <unistd.h>

#include <cstdio>
#include <memory>
#include <ostream>
#include <thread>

#include "cli/dds_log.hpp"
#include "common/log_records.hpp"
#include "common/record_file.hpp"
#include "connect.hpp"

namespace rigid::record {
namespace {

using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

std::int64_t unix_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

}  // namespace

int play(const RecordOptions& o, util::SignalWatcher& signals, std::ostream& err) {
  const clients::DdsLog dds_log;  // before the bus: Cyclone's lines are told in our words
  try {
    common::RecordReader reader(o.file);
    msgs::LogRecord r;
    if (!reader.next(r) || !r.has_header() || r.header().kind() != msgs::LogHeader::RECORDING) {
      err << "rigid-record: " << o.file
          << ": not a recording (rigid-record info says what it is)\n";
      return clients::kExitFailed;
    }
    rigid::SceneDescription scene;
    common::from_record(r.header().scene(), scene);
    // The server's role: this stands in for rigidd (and hears no one: commands are ignored).
    transport::Receiver deaf;
    const std::unique_ptr<transport::Transport> bus =
        client::connect(o.bus, transport::Role::kServer, deaf);
    (void)bus->publish(scene);
    const bool tty = ::isatty(STDERR_FILENO) == 1;
    rigid::StateFrame frame;
    std::int64_t played = 0;
    std::optional<std::int64_t> first_ns;
    const auto start = Clock::now();
    auto next_scene = start + 1s;
    auto next_line = start;
    while (reader.next(r)) {
      if (r.has_scene()) {
        common::from_record(r.scene(), scene);
        (void)bus->publish(scene);
        continue;
      }
      if (!r.has_state() || !common::from_record(r.state(), frame)) continue;
      if (!first_ns) first_ns = r.state().recorded_ns();
      const auto due =
          start + std::chrono::nanoseconds(static_cast<std::int64_t>(
                      static_cast<double>(r.state().recorded_ns() - *first_ns) / o.speed));
      // Sleep in slices, so that a signal stops playback promptly.
      while (Clock::now() < due) {
        const auto slice = std::min<Clock::duration>(due - Clock::now(), 100ms);
        if (signals.wait(std::chrono::duration_cast<std::chrono::milliseconds>(slice))) {
          err << (tty ? "\n" : "") << "rigid-record: stopped after " << played << " states\n";
          return clients::kExitOk;
        }
      }
      frame.stamp_ns = unix_ns();
      (void)bus->publish(frame);
      ++played;
      const auto now = Clock::now();
      if (now >= next_scene) {  // LCM has no late-joiner durability: as rigidd, once a second
        (void)bus->publish(scene);
        next_scene = now + 1s;
      }
      if (now >= next_line) {
        char line[160];
        std::snprintf(line, sizeof line, "playing %s: %lld states, tick %lld, t = %.3f s",
                      o.file.c_str(), static_cast<long long>(played),
                      static_cast<long long>(frame.tick), frame.sim_time);
        err << (tty ? "\r" : "") << line << (tty ? "\x1b[K" : "\n");
        err.flush();
        next_line = now + (tty ? 250ms : 5000ms);
      }
    }
    err << (tty ? "\r" : "") << "played " << o.file << ": " << played << " states"
        << (reader.damage() ? " (up to its damaged tail: " + reader.damage()->reason + ")" : "")
        << (tty ? "\x1b[K\n" : "\n");
    return clients::kExitOk;
  } catch (const common::LogFileError& e) {
    err << "rigid-record: " << e.what() << '\n';
    return clients::kExitFailed;
  } catch (const client::BusError& e) {
    err << "rigid-record: " << clients::bus_error_line(e.what(), o.bus, dds_log) << '\n';
    return clients::kExitFailed;
  }
}

}  // namespace rigid::record
