// rigidd's loop under load, measured from outside as a client sees it (bench/loop/loop_bench.sh runs
// the whole set and compares with step_bench).
//
//   loop_bench realtime [--bodies 1000] [--duration 60] [--push-every-ms 20] [--rigidd PATH]
//     rigidd in realtime mode at 1 kHz, a state every 10 ticks (100 Hz) on the buses of
//     --transport (default both), a subscriber on each bus, and a controller on each bus pushing
//     its own body with a one-tick wrench every push-every-ms plus a random fraction of a
//     millisecond. Reports rigidd's overruns and tick lateness p50/p99/max over the whole run
//     (its closing log line), rigidd's own measure of command arrival to state sent per bus, and
//     per bus the client's wrench-to-state latency p50/p99/max: from the controller's publish call
//     to the arrival of the first state in which the pushed body's velocity changed (so it
//     includes the wrench's own trip to the server and the state's trip back). Before the
//     measured run each controller pushes until one push comes back, so that the run measures
//     the wrench path, not its discovery.
//   loop_bench echo [--bodies 1000] [--duration 60] [--at-once]
//     the same controllers and subscribers as realtime, against a stand-in for rigidd with no
//     physics and no hand-offs (bench/loop/echo_server.hpp, this program run as `loop_bench
//     echo-server`): its tick thread publishes the state itself, right after the tick in which a
//     wrench arrived. Its wrench-to-state latency is the floor under rigidd's on this machine and
//     bus; with --at-once the stand-in answers each wrench from the bus's receive thread as it
//     arrives, without waiting for a tick: the two trips over the bus alone.
//   loop_bench timer [--duration 60]
//     the machine's own timer, without rigidd: a SCHED_FIFO thread sleeping to 1 ms deadlines,
//     without and with a 100 us final spin (rigidd's --spin-us default); what tick lateness and
//     overruns cannot beat here.
//   loop_bench fast [--bodies 10000] [--duration 20] [--no-subscribers] [--rigidd PATH]
//     rigidd in fast mode (ticks back to back), a state every 10 ticks (100 Hz of simulated time)
//     on the buses; reports the cost per body-step of the whole loop: wall time / (ticks *
//     bodies), and the states each subscriber received per second. With --publish-every 1 rigidd
//     offers a state every tick, far more than any bus carries: the states received per second are
//     then what the bus sustains from rigidd to one subscriber (rigidd skips what its publisher
//     cannot send; the subscriber misses what the bus drops).
//   loop_bench paced [--bodies 1000] [--duration 10] [--steps 2000]
//     rigidd in lockstep, driven by back-to-back step requests of --steps ticks each (the probe
//     sends the next one when the last is answered): a step request hands over every state it
//     promises, each only once the publisher took the previous one, so nothing is skipped and the
//     loop sleeps while the bus works. The states received per second are then what the bus
//     carries when every state must arrive, without fast mode's loop spinning on a core of its own
//     (on a 2-core machine that core is half of what the bus, its cryptography and the
//     subscriber would otherwise share). The probe's identity needs `control` with --security.
//   loop_bench memory [--bodies 100000] [--duration 10] [--rigidd PATH]
//     rigidd's memory: realtime mode on the scene, no clients; from the first state it publishes
//     (its log's "ready:" line) on for --duration s. Reports, per body, its resident set then
//     (VmRSS of /proc/PID/status) and at its highest since it started (VmHWM: loading the scene
//     and building the world included), and the seconds from its start to its first state.
//
// realtime, fast and paced also report the CPU each of rigidd's threads took over the run, by
// thread name (RESULT thread_cpu_percent): the loop, its publishers and the step's workers, which
// decide between them whether ticks are late; and the major page faults each took (RESULT
// thread_major_faults): a page read back from disk stops a thread for as long as the read takes.
//
// Common options: --transport dds|lcm|dds,lcm (the buses rigidd publishes on and the probes use),
// --rate HZ (the scene's tick rate, default 1000; the timer's period in timer mode),
// --publish-every K (a state every K ticks, default 10), --point-masses (weightless point masses
// instead of the racket: the cheapest physics, so that the buses limit the state rate),
// --loaded-every K (every K-th racket from body 2 on carries a body-fixed thruster from the scene:
// it costs the step what a body a controller keeps pushing costs; 3: a third), --csv FILE
// (appends one row per bus, for bench/report/plot_loop.py), --histogram FILE (appends the tick lateness
// histogram, see below).
//
// Tick lateness histogram: rigidd logs its whole histogram when it stops (a line
// "rigidd: lateness_histogram_ns LOW:COUNT ..."), and that is written; a rigidd that does not
// (an older build) leaves the histogram of the per-second maxima from its Stats instead (what the
// worst tick of each second looked like). The CSV's `source` column says which.
//
// The bodies are step_bench's "racket" case (I = diag(1, 2, 3), w0 = (1e-3 + 1e-6 i, 5, 1e-3), no
// gravity, dt = 1 ms, the default integrator), so the fast figure compares directly with
// `step_bench --benchmark_filter=racket/exact_rotor4/10000`.
#include <fcntl.h>
#include <malloc.h>
#include <sched.h>
#include <signal.h>
#include <spawn.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <charconv>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "echo_server.hpp"
#include "transport/dds/dds_transport.hpp"
#include "transport/lcm/lcm_transport.hpp"

extern char** environ;

namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;
using rigid::Bus;

std::int64_t now_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

// The clock of the stamps on the wire (rigidd stamps each state with it when it publishes).
std::int64_t wall_ns() {
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

struct Options {
  std::string mode;
  int bodies = 0;
  double duration = 0;
  int push_every_ms = 20;
  bool subscribers = true;
  std::vector<Bus> buses{Bus::kDds, Bus::kLcm};
  std::string transport = "dds,lcm";
  int publish_every = 10;
  int rate_hz = 1000;  // the scene's tick rate (the timer's, in timer mode)
  int steps = 2000;    // paced: ticks per step request
  bool point_masses = false;
  int loaded_every = 0;  // 0: no body carries a load from the scene
  std::string csv, histogram;
  std::string rigidd = RIGIDD_EXE;
  std::vector<std::string> rigidd_args;  // --rigidd-arg, passed on
  // --security KEYSTORE (made by scripts/rigid-keys, with an identity "bench" that may push):
  // rigidd runs as KEYSTORE/identities/rigidd, the DDS probes as KEYSTORE/identities/bench.
  std::string security;
  bool at_once = false;  // echo: answer each wrench as it arrives
  std::string prefix;    // echo-server: the topics' prefix
};

Options parse(int argc, char** argv) {
  Options o;
  if (argc < 2) {
    throw std::invalid_argument(
        "usage: loop_bench realtime|fast|paced|echo|timer|memory [options]");
  }
  o.mode = argv[1];
  if (o.mode == "--help" || o.mode == "-h") {
    o.mode = "help";
    return o;
  }
  if (o.mode != "realtime" && o.mode != "fast" && o.mode != "paced" && o.mode != "timer" &&
      o.mode != "memory" && o.mode != "echo" && o.mode != "echo-server") {
    throw std::invalid_argument("expected realtime, fast, paced, echo, timer or memory, got '" +
                                o.mode + "'");
  }
  o.bodies = o.mode == "fast" ? 10000 : o.mode == "memory" ? 100000 : 1000;
  o.duration = o.mode == "realtime" || o.mode == "echo"  ? 60
               : o.mode == "paced" || o.mode == "memory" ? 10
                                                         : 20;
  if (o.mode == "paced") o.publish_every = 1;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::invalid_argument(a + " needs a value");
      return argv[++i];
    };
    if (a == "--bodies") {
      o.bodies = std::stoi(value());
    } else if (a == "--duration") {
      o.duration = std::stod(value());
    } else if (a == "--push-every-ms") {
      o.push_every_ms = std::stoi(value());
    } else if (a == "--no-subscribers") {
      o.subscribers = false;
    } else if (a == "--transport") {
      o.transport = value();
      o.buses.clear();
      if (o.transport == "dds" || o.transport == "dds,lcm" || o.transport == "lcm,dds")
        o.buses.push_back(Bus::kDds);
      if (o.transport == "lcm" || o.transport == "dds,lcm" || o.transport == "lcm,dds")
        o.buses.push_back(Bus::kLcm);
      if (o.buses.empty()) throw std::invalid_argument("--transport: dds, lcm or dds,lcm");
    } else if (a == "--steps") {
      o.steps = std::stoi(value());
    } else if (a == "--publish-every") {
      o.publish_every = std::stoi(value());
    } else if (a == "--rate") {
      o.rate_hz = std::stoi(value());
    } else if (a == "--point-masses") {
      o.point_masses = true;
    } else if (a == "--loaded-every") {
      o.loaded_every = std::stoi(value());
    } else if (a == "--csv") {
      o.csv = value();
    } else if (a == "--histogram") {
      o.histogram = value();
    } else if (a == "--rigidd") {
      o.rigidd = value();
    } else if (a == "--rigidd-arg") {
      o.rigidd_args.push_back(value());
    } else if (a == "--security") {
      o.security = value();
    } else if (a == "--at-once") {
      o.at_once = true;
    } else if (a == "--prefix") {
      o.prefix = value();
    } else {
      throw std::invalid_argument("unknown option '" + a + "'");
    }
  }
  if (o.bodies < 2 || o.duration <= 0) throw std::invalid_argument("bad --bodies or --duration");
  if (o.publish_every < 1) throw std::invalid_argument("bad --publish-every");
  if (o.rate_hz < 1 || o.rate_hz > 10000) throw std::invalid_argument("--rate: 1 .. 10000 Hz");
  if (o.steps < 1) throw std::invalid_argument("bad --steps");
  if (o.loaded_every < 0) throw std::invalid_argument("bad --loaded-every");
  if (o.mode == "echo" && !o.security.empty()) {
    throw std::invalid_argument("--security: not with echo (the stand-in serves plain DDS)");
  }
  if (o.at_once && o.mode != "echo" && o.mode != "echo-server") {
    throw std::invalid_argument("--at-once: only with echo");
  }
  if (o.loaded_every > 0 && o.point_masses) {
    throw std::invalid_argument("--loaded-every needs the rackets, not --point-masses");
  }
  return o;
}

// step_bench's racket case as a scene file.
// With point_masses, weightless point masses instead (3-10 ns per body-step rather than ~50): the
// physics then leaves the buses as the limit of the state rate.
// With loaded_every K > 0, every K-th racket from body 2 on carries a constant body-fixed thruster
// off its centre (bodies 0 and 1 are the controllers': their states must change only when pushed).
std::string write_scene(const fs::path& dir, int bodies, int rate_hz, int publish_every,
                        bool point_masses, int loaded_every) {
  const fs::path path = dir / "bench.pbtxt";
  std::ofstream out(path);
  out << "world { rate_hz: " << rate_hz << " substeps: 1 publish_every: " << publish_every
      << " gravity { z: 0 } }\n";
  char line[256];
  for (int i = 0; i < bodies; ++i) {
    if (point_masses) {
      std::snprintf(line, sizeof line,
                    "body { name: \"b%d\" mass: 1 use_gravity: false velocity { x: %.17g } }\n", i,
                    1e-3 + 1e-6 * i);
    } else {
      std::snprintf(line, sizeof line,
                    "body { name: \"b%d\" mass: 1 inertia { x: 1 y: 2 z: 3 } use_gravity: false "
                    "angular_velocity { x: %.17g y: 5 z: 0.001 } }\n",
                    i, 1e-3 + 1e-6 * i);
    }
    out << line;
  }
  for (int i = 2; loaded_every > 0 && i < bodies; ++i) {
    if (i % loaded_every != 0) continue;
    std::snprintf(line, sizeof line,
                  "force { body: \"b%d\" force { z: 0.5 } point { x: 0.2 y: 0.05 } frame: BODY }\n",
                  i);
    out << line;
  }
  return path.string();
}

// rigidd as a child, stderr to a file; stopped with SIGTERM.
class Daemon {
 public:
  Daemon(const std::string& exe, const std::vector<std::string>& args, const fs::path& err)
      : err_(err) {
    std::vector<std::string> text{exe};
    text.insert(text.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (auto& t : text)
      argv.push_back(t.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 2, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (posix_spawn(&pid_, exe.c_str(), &actions, nullptr, argv.data(), environ) != 0) {
      throw std::runtime_error("cannot start " + exe);
    }
    posix_spawn_file_actions_destroy(&actions);
  }
  ~Daemon() { stop(); }
  pid_t pid() const { return pid_; }
  int stop() {
    if (pid_ <= 0) return status_;
    ::kill(pid_, SIGTERM);
    int status = 0;
    ::waitpid(pid_, &status, 0);
    pid_ = -1;
    status_ = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return status_;
  }
  std::string stderr_text() const {
    std::ifstream in(err_);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  }

 private:
  fs::path err_;
  pid_t pid_ = -1;
  int status_ = -1;
};

// rigidd's closing line, "stopped: ticks=... lateness_us p50=... p99=...": key=value pairs, with
// a bare word naming the group of the keys after it.
std::map<std::string, double> closing_figures(const std::string& log) {
  std::map<std::string, double> figures;
  const auto at = log.rfind("rigidd: stopped: ");
  if (at == std::string::npos) return figures;
  std::istringstream line(log.substr(at + 17, log.find('\n', at) - at - 17));
  std::string token, group;
  while (line >> token) {
    const auto eq = token.find('=');
    if (eq == std::string::npos) {
      group = token + ".";
      continue;
    }
    const std::string key = token.substr(0, eq);
    if (key != "p50" && key != "p99" && key != "max" && key != "n") group.clear();
    double v = 0;
    std::from_chars(token.data() + eq + 1, token.data() + token.size(), v);
    figures[group + key] = v;
  }
  return figures;
}

struct Percentiles {
  double p50 = 0, p99 = 0, max = 0;
  std::size_t n = 0;
};

Percentiles percentiles(std::vector<double> v) {
  Percentiles p;
  p.n = v.size();
  if (v.empty()) return p;
  std::sort(v.begin(), v.end());
  auto at = [&](double q) {
    const auto rank = static_cast<std::size_t>(std::ceil(q * static_cast<double>(v.size())));
    return v[std::min(v.size() - 1, rank == 0 ? 0 : rank - 1)];
  };
  p.p50 = at(0.5);
  p.p99 = at(0.99);
  p.max = v.back();
  return p;
}

// A client on one bus: counts states, and times wrenches on its own body until the first state
// that shows them.
class Probe final : public rigid::transport::Receiver {
 public:
  Probe(Bus bus, const std::string& prefix, int body, bool subscribe_states,
        const std::string& security = "")
      : bus_(bus), body_(body), subscribe_(subscribe_states) {
    if (bus == Bus::kDds) {
      rigid::transport::dds::Options o;
      o.role = rigid::transport::Role::kClient;
      o.prefix = prefix;
      o.security = security;
      transport_ = rigid::transport::dds::make_transport(o, *this);
    } else {
      rigid::transport::lcm::Options o;
      o.role = rigid::transport::Role::kClient;
      o.prefix = prefix;
      o.url = std::string(rigid::transport::lcm::kDefaultUrl) + "&recv_buf_size=8388608";
      transport_ = rigid::transport::lcm::make_transport(o, *this);
    }
  }
  ~Probe() override { transport_.reset(); }

  void on_state(const rigid::StateFrame& s) override {
    if (!subscribe_) return;
    const std::int64_t t = now_ns();
    const std::int64_t wall = wall_ns();
    const std::lock_guard lock(mutex_);
    ++states_;
    if (s.linear_velocity.size() <= static_cast<std::size_t>(3 * body_)) return;
    const double v = s.linear_velocity[static_cast<std::size_t>(3 * body_)];
    if (pending_ && v != v_before_) {
      latencies_us_.push_back(static_cast<double>(t - sent_ns_) * 1e-3);
      // The two legs: until rigidd published the state, and the state's trip to us.
      server_us_.push_back(static_cast<double>(s.stamp_ns - sent_wall_ns_) * 1e-3);
      wire_us_.push_back(static_cast<double>(wall - s.stamp_ns) * 1e-3);
      pending_ = false;
    }
    last_v_ = v;
    have_state_ = true;
  }
  void on_stats(const rigid::StatsReport& s) override {
    const std::lock_guard lock(mutex_);
    stats_.push_back(s);
  }
  void on_control_reply(const rigid::ControlReply& r) override {
    const std::lock_guard lock(mutex_);
    if (r.source != control_source() || r.seq != control_seq_) return;
    reply_ = r;
    replied_.notify_all();
  }

  // Asks rigidd (in lockstep) for `steps` ticks and waits for the answer, which comes when the
  // last of them is done; the reply, or none within `timeout`.
  std::optional<rigid::ControlReply> step(std::int64_t steps, std::chrono::milliseconds timeout) {
    rigid::ControlCommand c;
    c.source = control_source();
    c.command = rigid::ControlKind::kStep;
    c.steps = steps;
    std::unique_lock lock(mutex_);
    c.seq = ++control_seq_;
    reply_.reset();
    lock.unlock();
    (void)transport_->publish(c);
    lock.lock();
    replied_.wait_for(lock, timeout, [&] { return reply_.has_value(); });
    return reply_;
  }

  bool ready() {
    const std::lock_guard lock(mutex_);
    return have_state_;
  }
  // One-tick push along x, alternating sign so the velocity returns to where it was.
  void push() {
    rigid::WrenchCommand w;
    w.source = 1000 + static_cast<int>(bus_);
    w.seq = ++seq_;
    w.body_id = body_;
    w.body_name = "b" + std::to_string(body_);  // the scene's name (DDS Security needs it)
    w.force = {(seq_ % 2) ? 1.0 : -1.0, 0, 0};
    w.ttl = 0;
    {
      const std::lock_guard lock(mutex_);
      if (pending_) ++lost_;  // the previous one never showed (a lost state or wrench)
      pending_ = true;
      v_before_ = last_v_;
      sent_wall_ns_ = wall_ns();
      sent_ns_ = now_ns();
    }
    w.stamp_ns = sent_wall_ns_;
    (void)transport_->publish(w);
  }
  Bus bus() const { return bus_; }
  // Forgets what was measured so far (the warm-up's pushes).
  void reset_measures() {
    const std::lock_guard lock(mutex_);
    latencies_us_.clear();
    server_us_.clear();
    wire_us_.clear();
    lost_ = 0;
    pending_ = false;
  }
  std::vector<double> latencies() {
    const std::lock_guard lock(mutex_);
    return latencies_us_;
  }
  std::vector<double> server_legs() {
    const std::lock_guard lock(mutex_);
    return server_us_;
  }
  std::vector<double> wire_legs() {
    const std::lock_guard lock(mutex_);
    return wire_us_;
  }
  std::int64_t states() {
    const std::lock_guard lock(mutex_);
    return states_;
  }
  int lost() {
    const std::lock_guard lock(mutex_);
    return lost_;
  }
  std::vector<rigid::StatsReport> stats() {
    const std::lock_guard lock(mutex_);
    return stats_;
  }

 private:
  std::int64_t control_source() const { return 2000 + static_cast<int>(bus_); }

  const Bus bus_;
  const int body_;
  const bool subscribe_;
  std::mutex mutex_;
  std::condition_variable replied_;
  std::int64_t control_seq_ = 0;
  std::optional<rigid::ControlReply> reply_;
  std::int64_t seq_ = 0;
  bool pending_ = false;
  bool have_state_ = false;
  double v_before_ = 0, last_v_ = 0;
  std::int64_t sent_ns_ = 0;
  std::int64_t sent_wall_ns_ = 0;
  std::int64_t states_ = 0;
  int lost_ = 0;
  std::vector<double> latencies_us_;
  std::vector<double> server_us_;  // wrench sent -> state published (rigidd's stamp)
  std::vector<double> wire_us_;    // state published -> state received
  std::vector<rigid::StatsReport> stats_;
  std::unique_ptr<rigid::transport::Transport> transport_;
};

// Appends rows to a CSV, writing its header first when the file is new or empty.
void append_csv(const std::string& path, const std::string& header,
                const std::vector<std::string>& rows) {
  if (path.empty()) return;
  const bool fresh = !fs::exists(path) || fs::file_size(path) == 0;
  std::ofstream out(path, std::ios::app);
  if (!out) throw std::runtime_error("cannot write " + path);
  if (fresh) out << header << "\n";
  for (const auto& r : rows)
    out << r << "\n";
}

std::string fmt(const char* format, auto... args) {
  char buf[512];
  std::snprintf(buf, sizeof buf, format, args...);
  return buf;
}

constexpr const char* kCsvHeader =
    "run,mode,bodies,transport,publish_every,duration_s,spin_us,ticks,overruns,lateness_p50_us,"
    "lateness_p99_us,lateness_max_us,step_cost_p50_us,step_cost_p99_us,step_cost_max_us,bus,"
    "latency_p50_us,latency_p99_us,latency_max_us,latency_n,unseen,server_leg_p50_us,"
    "wire_leg_p50_us,command_to_state_p50_us,states_received_per_s,states_sent_per_s,"
    "states_skipped_per_s,state_bytes,ns_per_body_step";
constexpr const char* kHistogramHeader =
    "run,mode,bodies,transport,spin_us,source,low_us,high_us,count";

// A histogram of samples (us) as CSV rows, in the buckets of rigidd's own (loop/histogram.hpp):
// exact to the nanosecond below 128 ns, 64 per factor of 2 above, so that the report bins the
// timer's samples and rigidd's histogram alike.
std::vector<std::string> histogram_rows(const std::string& key, const std::string& source,
                                        const std::vector<double>& us) {
  std::map<std::pair<double, double>, long> bins;
  for (double v : us) {
    const double ns = std::max(0.0, std::round(v * 1000));
    double lo = ns, hi = ns + 1;
    if (ns >= 128) {
      const double octave = std::exp2(std::floor(std::log2(ns)));
      const double sub = std::floor((ns / octave - 1) * 64);
      lo = octave * (1 + sub / 64);
      hi = octave * (1 + (sub + 1) / 64);
    }
    ++bins[{lo, hi}];
  }
  std::vector<std::string> rows;
  for (const auto& [range, n] : bins)
    rows.push_back(fmt("%s,%s,%.6g,%.6g,%ld", key.c_str(), source.c_str(), range.first * 1e-3,
                       range.second * 1e-3, n));
  return rows;
}

// The platform's own timer: a bare thread at rigidd's loop priority (SCHED_FIFO 10, timer slack
// 1 ns) sleeping to absolute deadlines 1 / rate apart (1 ms by default), optionally spinning the
// last spin_us. What rigidd's tick lateness cannot beat on this machine.
int run_timer(const Options& o, std::int64_t spin_us) {
  sched_param param{};
  param.sched_priority = 10;
  const bool fifo = sched_setscheduler(0, SCHED_FIFO, &param) == 0;
  prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);
  const std::int64_t period_ns = 1'000'000'000 / o.rate_hz;
  const auto n = static_cast<std::size_t>(o.duration * o.rate_hz);
  std::vector<double> late;
  late.reserve(n);
  const std::int64_t t0 = now_ns() + period_ns;
  int over_1ms = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const std::int64_t deadline = t0 + static_cast<std::int64_t>(k) * period_ns;
    const std::int64_t wake = deadline - spin_us * 1000;
    timespec ts{static_cast<time_t>(wake / 1'000'000'000), static_cast<long>(wake % 1'000'000'000)};
    clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr);
    while (now_ns() < deadline) {
    }
    const std::int64_t l = now_ns() - deadline;
    late.push_back(static_cast<double>(l) * 1e-3);
    over_1ms += l > period_ns;
  }
  const Percentiles p = percentiles(late);
  std::printf(
      "RESULT timer_lateness_us spin %lld%s p50 %.1f p99 %.1f max %.1f, late by more "
      "than a tick: %d of %zu\n",
      static_cast<long long>(spin_us), fifo ? "" : " (no SCHED_FIFO)", p.p50, p.p99, p.max,
      over_1ms, p.n);
  append_csv(
      o.csv, kCsvHeader,
      {fmt("%d,timer,0,none,0,%.1f,%lld,%zu,%d,%.2f,%.2f,%.2f,,,,,,,,,,,,,,,,,", ::getpid(),
           o.duration, static_cast<long long>(spin_us), p.n, over_1ms, p.p50, p.p99, p.max)});
  // Every tick, and the worst of each second (to set beside rigidd's per-second maxima).
  std::vector<double> second_max;
  const auto per_second = static_cast<std::size_t>(o.rate_hz);
  for (std::size_t k = 0; k < late.size(); k += per_second) {
    const auto from = late.begin() + static_cast<std::ptrdiff_t>(k);
    second_max.push_back(*std::max_element(
        from,
        from + static_cast<std::ptrdiff_t>(std::min<std::size_t>(per_second, late.size() - k))));
  }
  const std::string key = fmt("%d,timer,0,none,%lld", ::getpid(), static_cast<long long>(spin_us));
  append_csv(o.histogram, kHistogramHeader, histogram_rows(key, "timer_samples", late));
  append_csv(o.histogram, kHistogramHeader,
             histogram_rows(key, "timer_per_second_max", second_max));
  return 0;
}

// rigidd's whole lateness histogram, when it logs one ("rigidd: lateness_histogram_ns" followed
// by LOW:COUNT pairs, LOW the bucket's lower bound in ns): rows of (low_us, high_us, count), the
// high bound being the next bucket's low.
std::vector<std::string> rigidd_histogram(const std::string& log, const std::string& key) {
  const std::string tag = "rigidd: lateness_histogram_ns";
  const auto at = log.rfind(tag);
  if (at == std::string::npos) return {};
  std::istringstream line(log.substr(at + tag.size(), log.find('\n', at) - at - tag.size()));
  std::vector<std::pair<double, long>> buckets;
  for (std::string token; line >> token;) {
    const auto colon = token.find(':');
    if (colon == std::string::npos) continue;
    buckets.emplace_back(std::stod(token.substr(0, colon)) * 1e-3,
                         std::stol(token.substr(colon + 1)));
  }
  std::vector<std::string> rows;
  for (std::size_t i = 0; i < buckets.size(); ++i) {
    const double lo = buckets[i].first;
    // Log-linear buckets: without the next one's bound, the width is that of this octave's.
    const double hi = i + 1 < buckets.size() ? std::min(buckets[i + 1].first, lo * 1.016 + 1e-3)
                                             : lo * 1.016 + 1e-3;
    rows.push_back(
        fmt("%s,rigidd_histogram,%.4g,%.4g,%ld", key.c_str(), lo, hi, buckets[i].second));
  }
  return rows;
}

// CPU time so far (user + system, in clock ticks) of each of process pid's threads, summed by
// thread name: rigidd names its own (rigid-loop, rigid-pub-dds, rigid-step-1, ...), Cyclone DDS
// its own (recv, tev, dq.builtins, ...). proc(5): /proc/PID/task/TID/stat, the name between the
// first '(' and the last ')', utime and stime fields 14 and 15.
// Per thread name (threads of one name summed): CPU time in clock ticks and major page faults
// (a page read back from disk: a code page the kernel dropped, for instance), from
// /proc/PID/task/*/stat.
struct ThreadUse {
  long ticks = 0;
  long major_faults = 0;
};
std::map<std::string, ThreadUse> thread_use(pid_t pid) {
  std::map<std::string, ThreadUse> use;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator("/proc/" + std::to_string(pid) + "/task", ec)) {
    std::ifstream in(e.path() / "stat");
    std::string stat((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::size_t open = stat.find('('), close = stat.rfind(')');
    if (open == std::string::npos || close == std::string::npos || close < open) continue;
    std::istringstream fields(stat.substr(close + 1));
    std::string f;
    ThreadUse& u = use[stat.substr(open + 1, close - open - 1)];
    for (int k = 3; k <= 15 && fields >> f; ++k) {
      if (k == 12) u.major_faults += std::atol(f.c_str());
      if (k == 14 || k == 15) u.ticks += std::atol(f.c_str());
    }
  }
  return use;
}
void print_thread_use(const std::map<std::string, ThreadUse>& before,
                      const std::map<std::string, ThreadUse>& after, double seconds) {
  const double per_tick = 100.0 / (static_cast<double>(::sysconf(_SC_CLK_TCK)) * seconds);
  std::vector<std::pair<double, std::string>> shares;
  std::vector<std::pair<long, std::string>> faults;
  for (const auto& [name, u] : after) {
    const auto b = before.find(name);
    const ThreadUse u0 = b == before.end() ? ThreadUse{} : b->second;
    const double percent = static_cast<double>(u.ticks - u0.ticks) * per_tick;
    if (percent >= 0.5) shares.emplace_back(percent, name);
    if (u.major_faults > u0.major_faults)
      faults.emplace_back(u.major_faults - u0.major_faults, name);
  }
  std::sort(shares.rbegin(), shares.rend());
  std::sort(faults.rbegin(), faults.rend());
  std::printf("RESULT thread_cpu_percent");
  for (const auto& [percent, name] : shares)
    std::printf(" %s %.1f", name.c_str(), percent);
  std::printf(" (rigidd's threads, %% of one CPU over %.1f s)\n", seconds);
  std::printf("RESULT thread_major_faults");
  for (const auto& [n, name] : faults)
    std::printf(" %s %ld", name.c_str(), n);
  std::printf("%s (rigidd's threads, over %.1f s)\n", faults.empty() ? " none" : "", seconds);
}

// A field of /proc/PID/status in bytes ("VmRSS:   1234 kB"), or -1.
double status_bytes(pid_t pid, const std::string& field) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind(field + ":", 0) != 0) continue;
    return 1024.0 * std::strtod(line.c_str() + field.size() + 1, nullptr);
  }
  return -1;
}

int run_memory(const Options& o, const std::string& scene, const std::vector<std::string>& args,
               const fs::path& dir) {
  const auto start = std::chrono::steady_clock::now();
  Daemon daemon(o.rigidd, args, dir / "rigidd.err");
  // Loading a large scene takes a while (10^6 bodies: ~40 s here).
  while (daemon.stderr_text().find("rigidd: ready:") == std::string::npos) {
    if (std::chrono::steady_clock::now() - start > 600s) {
      std::fprintf(stderr, "rigidd published no state within 600 s:\n%s",
                   daemon.stderr_text().c_str());
      return 1;
    }
    std::this_thread::sleep_for(50ms);
  }
  const double first_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::this_thread::sleep_for(std::chrono::duration<double>(o.duration));
  const double rss = status_bytes(daemon.pid(), "VmRSS");
  const double peak = status_bytes(daemon.pid(), "VmHWM");
  if (daemon.stop() != 0 || rss < 0 || peak < 0) {
    std::fprintf(stderr, "rigidd did not run or stop cleanly:\n%s", daemon.stderr_text().c_str());
    return 1;
  }
  std::printf(
      "RESULT rigidd_memory bodies %d rss_bytes_per_body %.0f peak_bytes_per_body %.0f "
      "first_state_s %.1f (scene %s)\n",
      o.bodies, rss / o.bodies, peak / o.bodies, first_s, scene.c_str());
  return 0;
}

// The echo stand-in's run: per bus the client's wrench-to-state latency and its two legs.
int report_echo(const Options& o, const std::vector<std::unique_ptr<Probe>>& probes,
                const std::vector<std::int64_t>& received, double wall, int status,
                const std::string& log) {
  if (status != 0) {
    std::fprintf(stderr, "the echo server did not stop cleanly (status %d):\n%s", status,
                 log.c_str());
    return 1;
  }
  std::printf("  %s", log.c_str());
  int measured = 0;
  for (std::size_t k = 0; k < probes.size(); ++k) {
    Probe& p = *probes[k];
    const std::string bus(to_string(o.buses[k]));
    const Percentiles l = percentiles(p.latencies());
    const Percentiles a = percentiles(p.server_legs());
    const Percentiles b = percentiles(p.wire_legs());
    std::printf(
        "RESULT echo_wrench_to_state_us %s%s p50 %.1f p99 %.1f max %.1f (n %zu, unseen "
        "%d, %.1f states/s)\n",
        bus.c_str(), o.at_once ? " at_once" : "", l.p50, l.p99, l.max, l.n, p.lost(),
        static_cast<double>(received[k]) / wall);
    std::printf(
        "  of which: wrench sent -> state published p50 %.1f p99 %.1f max %.1f; "
        "published -> received p50 %.1f p99 %.1f max %.1f\n",
        a.p50, a.p99, a.max, b.p50, b.p99, b.max);
    measured += l.n > 0;
  }
  if (measured < static_cast<int>(probes.size())) {
    std::fprintf(stderr, "loop_bench echo: no push came back on some bus\n");
    return 1;
  }
  return 0;
}

int run(const Options& o) {
  if (o.mode == "timer") {
    run_timer(o, 0);
    return run_timer(o, 100);
  }
  if (o.mode == "echo-server") {
    rigid::bench::EchoOptions e;
    e.prefix = o.prefix;
    e.buses = o.buses;
    e.bodies = o.bodies;
    e.rate_hz = o.rate_hz;
    e.publish_every = o.publish_every;
    e.at_once = o.at_once;
    return rigid::bench::run_echo_server(e);
  }
  const fs::path dir = fs::temp_directory_path() / ("loop_bench_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string scene =
      write_scene(dir, o.bodies, o.rate_hz, o.publish_every, o.point_masses, o.loaded_every);
  const std::string prefix = "bench" + std::to_string(::getpid());
  std::printf("loop_bench %s: %d bodies (%s%s), %d Hz, a state every %d ticks on %s, %.0f s\n",
              o.mode.c_str(), o.bodies,
              o.point_masses ? "point masses" : "step_bench's racket case",
              o.loaded_every > 0
                  ? (", every " + std::to_string(o.loaded_every) + "th with a thruster").c_str()
                  : "",
              o.rate_hz, o.publish_every, o.transport.c_str(), o.duration);

  if (o.mode == "memory") {
    std::vector<std::string> args{"--scene", scene, "--prefix", prefix, "--transport", o.transport};
    args.insert(args.end(), o.rigidd_args.begin(), o.rigidd_args.end());
    const int status = run_memory(o, scene, args, dir);
    fs::remove_all(dir);
    return status;
  }

  // Subscribers first, so rigidd's first states find them. Body 0 is the DDS controller's, body 1
  // the LCM one's.
  std::vector<std::unique_ptr<Probe>> probes;
  for (Bus bus : o.buses)
    probes.push_back(
        std::make_unique<Probe>(bus, prefix, bus == Bus::kDds ? 0 : 1, o.subscribers,
                                o.security.empty() ? "" : o.security + "/identities/bench"));
  const bool echo = o.mode == "echo";
  const std::string mode = o.mode == "paced" ? "lockstep" : o.mode;
  std::vector<std::string> args{"--scene", scene,         "--mode",    mode,       "--prefix",
                                prefix,    "--transport", o.transport, "--verbose"};
  args.insert(args.end(), o.rigidd_args.begin(), o.rigidd_args.end());
  if (!o.security.empty()) {
    args.push_back("--security");
    args.push_back(o.security + "/identities/rigidd");
  }
  if (echo) {
    args = {"echo-server",
            "--prefix",
            prefix,
            "--transport",
            o.transport,
            "--bodies",
            std::to_string(o.bodies),
            "--rate",
            std::to_string(o.rate_hz),
            "--publish-every",
            std::to_string(o.publish_every)};
    if (o.at_once) args.push_back("--at-once");
  }
  Daemon daemon(echo ? fs::read_symlink("/proc/self/exe").string() : o.rigidd, args,
                dir / "rigidd.err");
  const auto start = std::chrono::steady_clock::now();
  if (o.subscribers) {
    const auto all_ready = [&] {
      return std::all_of(probes.begin(), probes.end(), [](auto& p) { return p->ready(); });
    };
    while (!all_ready()) {
      if (std::chrono::steady_clock::now() - start > 30s) {
        std::fprintf(stderr, "no state from rigidd on every bus within 30 s:\n%s",
                     daemon.stderr_text().c_str());
        return 1;
      }
      std::this_thread::sleep_for(10ms);
    }
  }
  if (o.subscribers && (o.mode == "realtime" || echo)) {
    // A state reaching a probe says nothing of its wrenches reaching the server (on DDS their
    // writer and the server's reader discover each other on their own): each probe pushes until
    // one push comes back, and only then does the measured run start.
    const auto warm_up = std::chrono::steady_clock::now();
    for (auto& p : probes) {
      while (p->latencies().empty()) {
        if (std::chrono::steady_clock::now() - warm_up > 20s) {
          std::fprintf(stderr, "no push came back on %s within 20 s:\n%s",
                       std::string(to_string(p->bus())).c_str(), daemon.stderr_text().c_str());
          return 1;
        }
        p->push();
        std::this_thread::sleep_for(50ms);
      }
      p->reset_measures();
    }
  }
  const auto t0 = std::chrono::steady_clock::now();
  const auto end = t0 + std::chrono::duration<double>(o.duration);
  const std::map<std::string, ThreadUse> cpu0 = thread_use(daemon.pid());
  std::vector<std::int64_t> states0;
  for (auto& p : probes)
    states0.push_back(p->states());
  if (o.mode == "realtime" || echo) {
    // One controller per bus, each pushing every push-every-ms plus a random fraction of a tick:
    // a fixed period that is a whole number of ticks would always land at the same point of
    // rigidd's tick, and measure one arrival phase instead of all of them.
    std::vector<std::thread> controllers;
    for (std::size_t k = 0; k < probes.size(); ++k) {
      controllers.emplace_back([&, k] {
        std::mt19937 r(12345 + 666 * static_cast<unsigned>(k));
        std::uniform_int_distribution<int> phase_us(0, 999);
        for (auto next = t0; next < end; next += std::chrono::milliseconds(o.push_every_ms) +
                                                 std::chrono::microseconds(phase_us(r))) {
          std::this_thread::sleep_until(next);
          probes[k]->push();
        }
      });
    }
    for (auto& c : controllers)
      c.join();
  } else if (o.mode == "paced") {
    // Step requests back to back until the time is up (the last one may end a little after).
    std::int64_t requests = 0;
    while (std::chrono::steady_clock::now() < end) {
      const auto reply = probes.front()->step(o.steps, 60s);
      if (!reply || reply->outcome != rigid::Outcome::kOk) {
        std::fprintf(stderr, "step request %lld: %s\n%s", static_cast<long long>(requests + 1),
                     reply ? reply->message.c_str() : "no answer within 60 s",
                     daemon.stderr_text().c_str());
        return 1;
      }
      ++requests;
    }
    std::printf("  %lld step requests of %d ticks\n", static_cast<long long>(requests), o.steps);
  } else {
    std::this_thread::sleep_until(end);
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const std::map<std::string, ThreadUse> cpu1 = thread_use(daemon.pid());
  std::vector<std::int64_t> received;
  for (std::size_t k = 0; k < probes.size(); ++k)
    received.push_back(probes[k]->states() - states0[k]);
  std::this_thread::sleep_for(50ms);
  const int status = daemon.stop();
  const std::string log = daemon.stderr_text();
  if (echo) {
    fs::remove_all(dir);
    return report_echo(o, probes, received, wall, status, log);
  }
  const std::map<std::string, double> f = closing_figures(log);
  if (status != 0 || f.empty()) {
    std::fprintf(stderr, "rigidd did not stop cleanly (status %d):\n%s", status, log.c_str());
    return 1;
  }
  const auto fig = [&](const std::string& key) { return f.count(key) ? f.at(key) : NAN; };
  std::printf("  %s", log.substr(log.rfind("rigidd: stopped: ")).c_str());
  std::printf("  states received over %.1f s:", wall);
  for (std::size_t k = 0; k < probes.size(); ++k) {
    std::printf(" %s %lld (%.1f/s)", std::string(to_string(o.buses[k])).c_str(),
                static_cast<long long>(received[k]), static_cast<double>(received[k]) / wall);
  }
  std::printf("\n");
  print_thread_use(cpu0, cpu1, wall);
  const double loop_wall = fig("wall_s");
  const double ns_per_body_step = loop_wall * 1e9 / (fig("ticks") * o.bodies);
  // "both" rather than "dds,lcm" in the CSV.
  const std::string transport = o.buses.size() == 2 ? "both" : o.transport;
  const std::string key =
      fmt("%d,%s,%d,%s", ::getpid(), o.mode.c_str(), o.bodies, transport.c_str());
  std::vector<std::string> rows;
  if (o.mode == "realtime") {
    // The seconds in which ticks were skipped, from the Stats rigidd published each second.
    std::int64_t overruns_before = 0;
    std::vector<double> second_max;
    const auto stats = probes.front()->stats();
    for (const auto& st : stats) {
      if (st.overruns > overruns_before) {
        std::printf("  second ending at tick %lld: %lld tick(s) skipped, lateness max %.1f us\n",
                    static_cast<long long>(st.tick),
                    static_cast<long long>(st.overruns - overruns_before), st.lateness_max_us);
      }
      overruns_before = st.overruns;
      second_max.push_back(st.lateness_max_us);
    }
    std::printf("RESULT overruns %.0f\n", fig("overruns"));
    std::printf("RESULT tick_lateness_us p50 %.1f p99 %.1f max %.1f\n", fig("lateness_us.p50"),
                fig("lateness_us.p99"), fig("lateness_us.max"));
    std::printf("RESULT step_cost_us p50 %.1f p99 %.1f max %.1f\n", fig("step_cost_us.p50"),
                fig("step_cost_us.p99"), fig("step_cost_us.max"));
    std::vector<std::string> hist = rigidd_histogram(log, key + ",100");
    if (hist.empty()) hist = histogram_rows(key + ",100", "per_second_max", second_max);
    append_csv(o.histogram, kHistogramHeader, hist);
  } else if (o.mode == "fast") {
    std::printf("RESULT fast_ns_per_body_step %.2f (whole run: %.0f ticks in %.2f s)\n",
                ns_per_body_step, fig("ticks"), loop_wall);
    // Steady state: the per-second real-time factors from Stats (skipping the first second).
    std::vector<double> per_second;
    const auto stats = probes.front()->stats();
    for (std::size_t i = 1; i < stats.size(); ++i)
      if (stats[i].rtf_last_second > 0) per_second.push_back(1e-3 / stats[i].rtf_last_second);
    if (!per_second.empty()) {
      const Percentiles p = percentiles(per_second);
      std::printf("RESULT fast_ns_per_body_step_median_second %.2f (%zu seconds)\n",
                  p.p50 * 1e9 / o.bodies, p.n);
    }
  }
  // A state's size on the wire, roughly: 13 doubles and an id per body, plus a small header.
  const double state_bytes = 108.0 * o.bodies + 64;
  for (std::size_t k = 0; k < probes.size(); ++k) {
    Probe& p = *probes[k];
    const std::string bus(to_string(o.buses[k]));
    const double sent = fig(bus + "_states_sent"), skipped = fig(bus + "_states_skipped");
    const double per_s = static_cast<double>(received[k]) / wall;
    std::printf("RESULT states_per_s %s received %.1f sent %.1f skipped %.1f bodies_per_s %.4g\n",
                bus.c_str(), per_s, sent / loop_wall, skipped / loop_wall, per_s * o.bodies);
    Percentiles l, a, b;
    if (o.mode == "realtime") {
      l = percentiles(p.latencies());
      std::printf("RESULT wrench_to_state_us %s p50 %.1f p99 %.1f max %.1f (n %zu, unseen %d)\n",
                  bus.c_str(), l.p50, l.p99, l.max, l.n, p.lost());
      if (f.count(bus + "_command_to_state_us.p50")) {
        std::printf(
            "RESULT command_arrival_to_state_sent_us %s p50 %.1f p99 %.1f max %.1f "
            "(rigidd's own measure)\n",
            bus.c_str(), fig(bus + "_command_to_state_us.p50"),
            fig(bus + "_command_to_state_us.p99"), fig(bus + "_command_to_state_us.max"));
      }
      a = percentiles(p.server_legs());
      b = percentiles(p.wire_legs());
      std::printf(
          "  of which: wrench sent -> state published p50 %.1f p99 %.1f max %.1f; "
          "published -> received p50 %.1f p99 %.1f max %.1f\n",
          a.p50, a.p99, a.max, b.p50, b.p99, b.max);
    }
    const bool rt = o.mode == "realtime";
    rows.push_back(
        key +
        fmt(",%d,%.1f,100,%.0f,%.0f,%.2f,%.2f,%.2f,%.2f,%.2f,%.2f,%s,", o.publish_every, wall,
            fig("ticks"), fig("overruns"), fig("lateness_us.p50"), fig("lateness_us.p99"),
            fig("lateness_us.max"), fig("step_cost_us.p50"), fig("step_cost_us.p99"),
            fig("step_cost_us.max"), bus.c_str()) +
        (rt ? fmt("%.2f,%.2f,%.2f,%zu,%d,%.2f,%.2f,%.2f", l.p50, l.p99, l.max, l.n, p.lost(), a.p50,
                  b.p50, fig(bus + "_command_to_state_us.p50"))
            : std::string(",,,,,,,")) +
        fmt(",%.2f,%.2f,%.2f,%.0f,", per_s, sent / loop_wall, skipped / loop_wall, state_bytes) +
        (rt ? std::string() : fmt("%.3f", ns_per_body_step)));
  }
  append_csv(o.csv, kCsvHeader, rows);
  if (o.mode == "fast") {
    std::printf("  states skipped by the publishers:");
    for (Bus bus : o.buses) {
      const std::string name(to_string(bus));
      std::printf(" %s %.0f", name.c_str(), fig(name + "_states_skipped"));
    }
    std::printf(" of %.0f offered\n", fig("ticks") / o.publish_every);
  }
  fs::remove_all(dir);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  // As rigidd does: samples over 128 KiB would otherwise be mmapped and unmapped each time.
  mallopt(M_MMAP_THRESHOLD, 256 * 1024 * 1024);
  mallopt(M_TRIM_THRESHOLD, 512 * 1024 * 1024);
  try {
    const Options o = parse(argc, argv);
    if (o.mode == "help") {
      std::printf(
          "usage: loop_bench realtime|fast|paced|echo|timer|memory [--bodies N] [--duration S] "
          "[--transport dds|lcm|dds,lcm]\n"
          "                  [--rate HZ] [--publish-every K] [--point-masses] [--loaded-every K] "
          "[--push-every-ms MS] [--no-subscribers] [--steps N]\n"
          "                  [--csv FILE] [--histogram FILE] [--rigidd PATH] [--rigidd-arg "
          "ARG]... [--security KEYSTORE] [--at-once]\n"
          "rigidd from outside: tick lateness and wrench-to-state latency (realtime), cost per "
          "body-step or states per\nsecond a bus sustains (fast), states per second a bus carries "
          "when every one must arrive (paced),\nthe buses' floor under the wrench-to-state "
          "latency, "
          "without rigidd (echo), the machine's timer floor (timer), rigidd's memory "
          "per body (memory). See the comment "
          "at the top of bench/loop/loop_bench.cpp.\n");
      return 0;
    }
    return run(o);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "loop_bench: %s\n", e.what());
    return 2;
  }
}
