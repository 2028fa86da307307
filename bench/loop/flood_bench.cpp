// Does rigidd keep its rate under a flood of commands? For each bus in turn: rigidd in realtime
// mode at 1 kHz on a mixed scene (--bodies, default 100: boxes, cylinders, spheres and general
// bodies, gravity, drag, a state every 10 ticks), one controller flooding it with valid one-tick
// wrenches at --rate (default 10^5 per second) for --duration (default 5 s), and a separate
// monitor that records every state and Stats and, halfway through, sends one control request.
//
//   flood_bench [--rate N] [--duration S] [--bodies N] [--transport dds|lcm|dds,lcm] [--csv FILE]
//
// Reported per bus, over the flood (rigidd's own Stats before and after it, and what the monitor
// saw): commands sent (and the rate the sender achieved), received by rigidd, accepted, dropped by
// rigidd (queue full, counted in Stats), lost on the bus before rigidd (sent - received: a UDP
// socket buffer overrun on LCM, a DDS reader's history overwritten); the state rate and the tick
// rate the monitor saw; the worst per-second tick lateness p99 and max; overruns; and how long the
// control request took to be answered. --csv appends one row per bus (with a header if the file
// is new). Timing figures are for this machine at this moment: compare side by side.
#include <sys/utsname.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "bus_client.hpp"
#include "rigidd_process.hpp"

namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;
using rigid::Bus;
using rigid::StatsReport;
using rigid::rigidd::testing::BusClient;
using rigid::rigidd::testing::RigiddProcess;
using Clock = std::chrono::steady_clock;

struct Options {
  double rate = 1e5;  // commands per second
  double duration = 5.0;
  int bodies = 100;
  std::vector<Bus> buses{Bus::kLcm, Bus::kDds};
  std::string csv;
};

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::invalid_argument(a + " needs a value");
      return argv[++i];
    };
    if (a == "--rate") {
      o.rate = std::stod(value());
    } else if (a == "--duration") {
      o.duration = std::stod(value());
    } else if (a == "--bodies") {
      o.bodies = std::stoi(value());
    } else if (a == "--transport") {
      const std::string t = value();
      o.buses.clear();
      if (t.find("lcm") != std::string::npos) o.buses.push_back(Bus::kLcm);
      if (t.find("dds") != std::string::npos) o.buses.push_back(Bus::kDds);
      if (o.buses.empty()) throw std::invalid_argument("--transport: dds, lcm or dds,lcm");
    } else if (a == "--csv") {
      o.csv = value();
    } else if (a == "--help" || a == "-h") {
      std::puts(
          "flood_bench [--rate N] [--duration S] [--bodies N] [--transport dds|lcm|dds,lcm] "
          "[--csv FILE]");
      std::exit(0);
    } else {
      throw std::invalid_argument("unknown option '" + a + "'");
    }
  }
  if (o.rate <= 0 || o.duration <= 0 || o.bodies < 1) {
    throw std::invalid_argument("--rate, --duration and --bodies must be > 0");
  }
  return o;
}

// A scene a user might run: a mix of every body model, gravity, some drag, 1 kHz, 100 Hz states.
std::string write_scene(const fs::path& dir, int bodies) {
  const fs::path path = dir / "flood.pbtxt";
  std::ofstream out(path);
  out << "world { rate_hz: 1000 publish_every: 10 gravity { z: -9.81 } }\n";
  char line[320];
  for (int i = 0; i < bodies; ++i) {
    const double x = 0.5 * (i % 10), y = 0.5 * (i / 10), w = 0.5 + 0.01 * i;
    const char* shape = nullptr;
    switch (i % 4) {
      case 0:
        shape = "shape { box { x: 0.1 y: 0.25 z: 0.4 } } density: 500";
        break;
      case 1:
        shape = "shape { cylinder { radius: 0.2 length: 0.05 } } mass: 2";
        break;
      case 2:
        shape = "shape { sphere { radius: 0.1 } } density: 1000 linear_drag: 0.5";
        break;
      default:
        shape = "mass: 1 inertia { x: 1 y: 2 z: 3 } angular_drag: 0.01";
        break;
    }
    std::snprintf(line, sizeof line,
                  "body { name: \"b%d\" %s position { x: %g y: %g z: 10 } "
                  "angular_velocity { x: %g y: 3 z: 0.1 } }\n",
                  i, shape, x, y, w);
    out << line;
  }
  return path.string();
}

struct Result {
  Bus bus = Bus::kLcm;
  std::int64_t sent = 0;
  double send_rate = 0;  // achieved, per second
  std::int64_t received = 0, accepted = 0, dropped = 0, other_refused = 0;
  double state_hz = 0, tick_hz = 0;
  double lateness_p99_us = 0, lateness_max_us = 0;  // the worst second of the flood
  std::int64_t overruns = 0, states_skipped = 0;
  double control_ms = -1;  // -1: no answer
  std::string control_outcome;
  bool alive = false;
  int exit_code = -1;
};

const rigid::TransportCounts& counts_of(const StatsReport& s, Bus bus) {
  return bus == Bus::kDds ? s.dds : s.lcm;
}

std::int64_t refused(const StatsReport& s) {
  const auto& r = s.rejected;
  return r.non_finite + r.unknown_body + r.over_limit + r.stale_sequence + r.invalid;
}

// The first Stats published after `after` (by tick), within `patience`.
std::optional<StatsReport> next_stats(BusClient& c, std::int64_t after,
                                      std::chrono::milliseconds patience) {
  std::optional<StatsReport> s;
  c.wait(
      [&] {
        if (c.stats_locked() && c.stats_locked()->tick > after) s = c.stats_locked();
        return s.has_value();
      },
      patience);
  return s;
}

Result run_bus(const Options& o, Bus bus, const std::string& scene) {
  Result r;
  r.bus = bus;
  const std::string prefix = rigid::rigidd::testing::unique_prefix("flood");
  RigiddProcess rigidd({"--scene", scene, "--transport", bus == Bus::kDds ? "dds" : "lcm", "--mode",
                        "realtime", "--prefix", prefix});
  BusClient monitor(bus, prefix);
  BusClient flooder(bus, prefix);
  rigid::ControlCommand harmless;
  harmless.command = rigid::ControlKind::kSetRtf;
  harmless.rtf = 1.0;
  // Both clients heard (DDS discovery), and a Stats to start from.
  if (!monitor.handshake(harmless, 10s) || !flooder.handshake(harmless, 10s)) {
    throw std::runtime_error("no answer from rigidd:\n" + rigidd.stderr_text());
  }
  const auto first = next_stats(monitor, 0, 3s);
  if (!first) throw std::runtime_error("no Stats from rigidd");
  const StatsReport before = *next_stats(monitor, first->tick, 3s);

  // The flood, paced in 100 us slices on its own thread.
  std::atomic<std::int64_t> sent{0};
  const auto t0 = Clock::now();
  const auto end =
      t0 + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(o.duration));
  std::thread flood([&] {
    rigid::WrenchCommand w;
    w.ttl = 0;  // one tick
    std::int64_t n = 0;
    for (auto now = Clock::now(); now < end; now = Clock::now()) {
      const auto due =
          static_cast<std::int64_t>(o.rate * std::chrono::duration<double>(now - t0).count());
      for (; n < due; ++n) {
        w.body_id = static_cast<std::int32_t>(n % o.bodies);
        w.key = static_cast<std::int32_t>(n % 4);
        w.force = {0.1 * static_cast<double>(n % 7), 0, 1};
        flooder.send(w);
      }
      sent.store(n, std::memory_order_relaxed);
      std::this_thread::sleep_for(100us);
    }
    sent.store(n, std::memory_order_relaxed);
  });

  // Halfway: one control request from the monitor, as an operator would send it.
  std::this_thread::sleep_until(t0 + (end - t0) / 2);
  const auto c0 = Clock::now();
  const auto reply = monitor.request(harmless, 5s);
  if (reply) {
    r.control_ms = std::chrono::duration<double, std::milli>(Clock::now() - c0).count();
    r.control_outcome = reply->outcome == rigid::Outcome::kOk ? "ok" : reply->message;
  }
  // Every Stats of the flood, for its worst second.
  std::vector<StatsReport> during;
  std::int64_t last_tick = before.tick;
  while (Clock::now() < end + 1100ms) {
    if (const auto s = next_stats(monitor, last_tick, 200ms)) {
      last_tick = s->tick;
      during.push_back(*s);
    }
  }
  flood.join();
  r.sent = sent.load();
  r.send_rate = static_cast<double>(r.sent) / o.duration;

  // Quiet again: the counts stop moving once rigidd has taken in what was still on its way.
  StatsReport after = *next_stats(monitor, last_tick, 3s);
  for (int i = 0; i < 5; ++i) {
    const auto next = next_stats(monitor, after.tick, 3s);
    if (!next) break;
    const bool settled = counts_of(*next, bus).received == counts_of(after, bus).received;
    after = *next;
    if (settled) break;
  }
  r.received = counts_of(after, bus).received - counts_of(before, bus).received;
  r.accepted = after.commands_accepted - before.commands_accepted;
  r.dropped = after.rejected.queue_full - before.rejected.queue_full;
  r.other_refused = refused(after) - refused(before);
  r.overruns = after.overruns - before.overruns;
  r.states_skipped = after.states_skipped - before.states_skipped;
  for (const StatsReport& s : during) {
    r.lateness_p99_us = std::max(r.lateness_p99_us, s.lateness_p99_us);
    r.lateness_max_us = std::max(r.lateness_max_us, s.lateness_max_us);
  }

  // States the monitor received during the flood (from its first half-second on).
  const auto ns = [](Clock::time_point t) {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(t.time_since_epoch()).count();
  };
  const std::int64_t from = ns(t0 + 500ms), to = ns(end);
  std::int64_t count = 0, tick0 = -1, tick1 = -1, at0 = 0, at1 = 0;
  for (const auto& s : monitor.states()) {
    if (s.received_ns < from || s.received_ns > to) continue;
    ++count;
    if (tick0 < 0) {
      tick0 = s.state.tick;
      at0 = s.received_ns;
    }
    tick1 = s.state.tick;
    at1 = s.received_ns;
  }
  const double window = static_cast<double>(to - from) * 1e-9;
  r.state_hz = static_cast<double>(count) / window;
  r.tick_hz = at1 > at0
                  ? static_cast<double>(tick1 - tick0) / (static_cast<double>(at1 - at0) * 1e-9)
                  : 0.0;
  r.alive = rigidd.running();
  r.exit_code = rigidd.terminate(2000ms);
  return r;
}

std::string bus_name(Bus b) {
  return b == Bus::kDds ? "dds" : "lcm";
}

void print(const std::vector<Result>& results, const Options& o) {
  std::printf(
      "\nflood: %.0f commands/s for %g s, %d bodies at 1 kHz, a state every 10 ticks (100 Hz)\n\n",
      o.rate, o.duration, o.bodies);
  std::printf("%-4s %9s %9s %9s %9s %9s %8s %8s %8s %9s %9s %8s %10s\n", "bus", "sent", "sent/s",
              "received", "accepted", "dropped", "lost", "state", "tick", "late p99", "late max",
              "overruns", "control");
  std::printf("%-4s %9s %9s %9s %9s %9s %8s %8s %8s %9s %9s %8s %10s\n", "", "", "", "", "",
              "(Stats)", "(on bus)", "Hz", "Hz", "us", "us", "", "ms");
  for (const Result& r : results) {
    std::printf("%-4s %9lld %9.0f %9lld %9lld %9lld %8lld %8.1f %8.1f %9.1f %9.1f %8lld %10.1f\n",
                bus_name(r.bus).c_str(), static_cast<long long>(r.sent), r.send_rate,
                static_cast<long long>(r.received), static_cast<long long>(r.accepted),
                static_cast<long long>(r.dropped), static_cast<long long>(r.sent - r.received),
                r.state_hz, r.tick_hz, r.lateness_p99_us, r.lateness_max_us,
                static_cast<long long>(r.overruns), r.control_ms);
  }
  std::printf("\n");
  for (const Result& r : results) {
    std::printf(
        "%s: accepted + dropped + refused = %lld of %lld received%s; control answered: %s; "
        "rigidd %s, exit status %d after SIGTERM\n",
        bus_name(r.bus).c_str(), static_cast<long long>(r.accepted + r.dropped + r.other_refused),
        static_cast<long long>(r.received),
        r.accepted + r.dropped + r.other_refused == r.received ? " (none uncounted)" : "",
        r.control_ms < 0 ? "no" : r.control_outcome.c_str(), r.alive ? "alive to the end" : "DIED",
        r.exit_code);
  }
}

void write_csv(const std::vector<Result>& results, const Options& o) {
  const bool fresh = !fs::exists(o.csv);
  std::ofstream out(o.csv, std::ios::app);
  if (!out) throw std::runtime_error("cannot write " + o.csv);
  if (fresh) {
    out << "host,bus,rate,duration_s,bodies,sent,received,accepted,dropped,refused,lost_on_bus,"
           "state_hz,tick_hz,lateness_p99_us_worst_second,lateness_max_us,overruns,"
           "states_skipped,control_ms\n";
  }
  utsname u{};
  ::uname(&u);
  for (const Result& r : results) {
    out << u.nodename << ',' << bus_name(r.bus) << ',' << o.rate << ',' << o.duration << ','
        << o.bodies << ',' << r.sent << ',' << r.received << ',' << r.accepted << ',' << r.dropped
        << ',' << r.other_refused << ',' << r.sent - r.received << ',' << r.state_hz << ','
        << r.tick_hz << ',' << r.lateness_p99_us << ',' << r.lateness_max_us << ',' << r.overruns
        << ',' << r.states_skipped << ',' << r.control_ms << '\n';
  }
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const Options o = parse(argc, argv);
    // The loopback DDS configuration the tests use, unless the caller chose one; rigidd inherits
    // it.
    ::setenv("CYCLONEDDS_URI", "file://" RIGID_SOURCE_DIR "/config/cyclonedds.xml", 0);
    const fs::path dir = fs::temp_directory_path() / ("flood_bench_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const std::string scene = write_scene(dir, o.bodies);
    std::vector<Result> results;
    for (const Bus bus : o.buses) {
      std::fprintf(stderr, "flood_bench: %s...\n", bus_name(bus).c_str());
      results.push_back(run_bus(o, bus, scene));
    }
    fs::remove_all(dir);
    print(results, o);
    if (!o.csv.empty()) write_csv(results, o);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "flood_bench: %s\n", e.what());
    return 1;
  }
}
