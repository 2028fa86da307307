// rigid-view: rigidd in a web browser. Wiring: the SDK's Session (states, scene, Stats, controls,
// wrenches), a pump that sends the newest state to the pages at most kFrameRate times a second,
// a worker that carries out the pages' control requests one at a time, and the HTTP/WebSocket
// server (server.hpp).
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <deque>
#include <exception>
#include <filesystem>
#include <iostream>
#include <map>
#include <mutex>
#include <optional>
#include <string_view>
#include <thread>
#include <tuple>
#include <vector>

#include "cli/dds_log.hpp"
#include "cli/state_rows.hpp"
#include "common/foxglove_messages.hpp"
#include "common/log_records.hpp"
#include "common/wrench_table.hpp"
#include "drift.hpp"
#include "playback_viewer.hpp"
#include "protocol.hpp"
#include "rigid.pb.h"
#include "rigid/client/names.hpp"
#include "rigid/client/session.hpp"
#include "server.hpp"
#include "util/signal_watcher.hpp"
#include "view_options.hpp"

namespace {

using namespace rigid;
using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

constexpr double kFrameRate = 60;
constexpr std::size_t kMaxPendingControls = 8;
constexpr auto kControlPatience = 3s;
constexpr double kPushTtl = 0.1;         // s of simulated time; re-sent each frame
constexpr auto kMinPushInterval = 10ms;  // per page
constexpr std::size_t kMaxPushingPages = 64;
constexpr std::size_t kMaxWrenchesKept = 1024;   // accepted wrenches held for the pages' arrows
constexpr std::size_t kMaxPendingDrives = 4096;  // wrenches not yet told to the drift tracker

// web/ next to the executable (the build tree), else ../share/rigid/web from it (cmake --install).
std::filesystem::path default_web_dir() {
  std::error_code ec;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) return "web";
  const std::filesystem::path beside = exe.parent_path() / "web";
  if (std::filesystem::exists(beside / "index.html", ec)) return beside;
  const std::filesystem::path installed = exe.parent_path().parent_path() / "share/rigid/web";
  if (std::filesystem::exists(installed / "index.html", ec)) return installed;
  return beside;  // missing: rigid-view says so, naming this directory
}

struct Job {
  view::PageCommand command;
  std::function<void(view::Bytes)> reply;
};

class Viewer {
 public:
  Viewer(const view::ViewOptions& o, client::Session& session) : session_(session) {
    view::ServerOptions so;
    so.host = o.host;
    so.port = o.port;
    so.read_only = o.read_only;
    so.web_dir = o.web_dir.empty() ? default_web_dir() : std::filesystem::path(o.web_dir);
    so.foxglove_origins = o.foxglove_origins;
    server_ = std::make_unique<view::ViewServer>(
        so,
        [this](std::uint64_t page, const view::PageCommand& c,
               std::function<void(view::Bytes)> reply) { command(page, c, std::move(reply)); },
        [this] { return greeting(); },
        [this](view::foxglove::Channel channel) { return foxglove_latest(channel); });
  }

  std::uint16_t port() const { return server_->port(); }
  std::string address() const { return server_->address(); }
  bool listens_beyond_host() const { return server_->listens_beyond_host(); }

  void start() {
    session_.on_each_state([this](const StateFrame& s) {
      {
        const std::lock_guard lock(mutex_);
        latest_ = s;
        fresh_ = true;
      }
      fresh_state_.notify_one();
    });
    session_.on_each_scene([this](const SceneDescription& d) { set_scene(d); });
    session_.on_each_accepted([this](const AcceptedCommand& a) { accepted(a); });
    session_.on_each_stats([this](const StatsReport& s) {
      auto text = std::make_shared<const std::string>(view::stats_json(s));
      {
        const std::lock_guard lock(mutex_);
        stats_text_ = text;
        stats_ = s;
      }
      server_->broadcast_text(text);
      if (server_->foxglove_subscribed(Channel::kStats))
        server_->broadcast_foxglove(Channel::kStats, foxglove_stats(s));
    });
    server_->start();
    pump_ = std::thread([this] { pump(); });
    worker_ = std::thread([this] { work(); });
  }

  void stop() {
    {
      const std::lock_guard lock(mutex_);
      stopping_ = true;
    }
    wake_.notify_all();
    fresh_state_.notify_one();
    if (pump_.joinable()) pump_.join();
    if (worker_.joinable()) worker_.join();
    session_.on_each_state({});
    session_.on_each_scene({});
    session_.on_each_stats({});
    session_.on_each_accepted({});
    server_->stop();
  }

  const view::ServerCounts& counts() const { return server_->counts(); }

 private:
  // A SceneInfo that differs from the one drawn (LCM repeats it every second).
  void set_scene(const SceneDescription& d) {
    view::Bytes text;
    std::map<std::string, std::int32_t, std::less<>> ids;
    {
      const std::lock_guard lock(mutex_);
      if (scene_ && *scene_ == d) return;
      scene_ = d;
      ++generation_;
      text = std::make_shared<const std::string>(view::scene_json(d, generation_));
      scene_text_ = text;
      names_ = clients::BodyNames(d);
      for (std::size_t i = 0; i < d.ids.size() && i < d.names.size(); ++i)
        ids.emplace(d.names[i], d.ids[i]);
    }
    server_->broadcast_text(text);
    server_->set_body_ids(std::move(ids));
    for (const Channel c : {Channel::kBodies, Channel::kScene})
      if (server_->foxglove_subscribed(c)) server_->broadcast_foxglove(c, foxglove_latest(c));
  }

  // Foxglove (docs/foxglove.md). Messages are made only for channels some client subscribes to:
  // without Foxglove clients rigid-view does what it did without them.
  using Channel = view::foxglove::Channel;

  static std::uint64_t wall_ns() {
    return static_cast<std::uint64_t>(std::chrono::system_clock::now().time_since_epoch() /
                                      std::chrono::nanoseconds(1));
  }

  static view::FoxgloveMessage foxglove_stats(const StatsReport& s) {
    msgs::StatsRecord r;
    common::to_record(s, 0, r);
    return {std::make_shared<const std::string>(r.SerializeAsString()), wall_ns()};
  }

  // The newest message of a channel: for a client that subscribes, and (kBodies, kScene) for a
  // scene change. Any thread but the pump's (which holds mutex_ while it encodes).
  view::FoxgloveMessage foxglove_latest(Channel channel) {
    const std::lock_guard lock(mutex_);
    switch (channel) {
      case Channel::kBodies:
        if (!scene_) return {};
        // Every entity of the topic replaced: bodies of an earlier scene go.
        return {std::make_shared<const std::string>(
                    common::foxglove::scene_update(*scene_, wall_ns(), true)),
                wall_ns()};
      case Channel::kScene: {
        if (!scene_) return {};
        msgs::SceneRecord r;
        common::to_record(*scene_, 0, r);
        return {std::make_shared<const std::string>(r.SerializeAsString()), wall_ns()};
      }
      case Channel::kStats:
        return stats_ ? foxglove_stats(*stats_) : view::FoxgloveMessage{};
      case Channel::kTransforms:
      case Channel::kBodyStates:
      case Channel::kState:
        return latest_ ? foxglove_state(channel, *latest_) : view::FoxgloveMessage{};
    }
    return {};
  }

  // A state as one of the state channels' messages, its time rigidd's stamp. mutex_ held (the
  // bodies' names by id come from the scene).
  view::FoxgloveMessage foxglove_state(Channel channel, const StateFrame& s) {
    if (!std::equal(s.ids.begin(), s.ids.end(), name_ids_.begin(), name_ids_.end()) ||
        names_generation_ != generation_) {
      name_ids_ = s.ids;
      names_generation_ = generation_;
      state_names_.clear();
      for (const std::int32_t id : s.ids)
        state_names_.push_back(names_.name(id));
    }
    const std::uint64_t time = s.stamp_ns > 0 ? static_cast<std::uint64_t>(s.stamp_ns) : wall_ns();
    auto out = std::make_shared<std::string>();
    switch (channel) {
      case Channel::kTransforms:
        common::foxglove::append_frame_transforms(*out, state_names_, s.position.data(),
                                                  s.orientation.data(), time);
        break;
      case Channel::kBodyStates:
        common::foxglove::append_body_states(*out, s, state_names_);
        break;
      case Channel::kState: {
        msgs::StateRecord r;
        common::to_record(s, 0, r);
        r.AppendToString(out.get());
        break;
      }
      default:
        return {};
    }
    return {std::move(out), time};
  }

  // Bus thread: the newest accepted wrench per (source, body, key), bounded; the pump forwards
  // them to the pages at most kWrenchRate times a second, whatever rate controllers send at.
  void accepted(const AcceptedCommand& a) {
    if (a.kind == AcceptedKind::kEdit) {
      // An edit changes its body's energy and momentum, which is not drift: its reference is
      // taken again (drift.hpp), as for a wrench of one tick.
      const std::lock_guard lock(mutex_);
      if (drives_.size() < kMaxPendingDrives) drives_.push_back(Drive{a.body_id, a.tick, 0.0});
      return;
    }
    if (a.kind != AcceptedKind::kWrench) return;
    const std::lock_guard lock(mutex_);
    if (drives_.size() < kMaxPendingDrives) drives_.push_back(Drive{a.body_id, a.tick, a.ttl});
    const WrenchKey key{a.source, a.body_id, a.key};
    if (wrenches_.size() >= kMaxWrenchesKept && !wrenches_.contains(key)) {
      auto oldest = wrenches_.begin();  // full (a flood of keys): the oldest makes room
      for (auto it = wrenches_.begin(); it != wrenches_.end(); ++it)
        if (it->second.tick < oldest->second.tick) oldest = it;
      wrenches_.erase(oldest);
    }
    wrenches_[key] = a;
    wrenches_changed_ = true;
  }

  // Pump thread, mutex held: the accepted wrenches still acting at `tick` (for rigidd's
  // ticks_to_live(ttl, dt) ticks from theirs, as the page draws them), newest last; forgets the
  // others. Nothing when nothing changed.
  std::optional<std::vector<AcceptedCommand>> acting_wrenches(std::int64_t tick) {
    const double dt = scene_ && scene_->dt > 0 ? scene_->dt : 0;
    for (auto it = wrenches_.begin(); it != wrenches_.end();) {
      const double ttl = it->second.ttl;
      const double ticks = dt > 0 && ttl >= 0 && ttl / dt <= 1e12
                               ? static_cast<double>(common::ticks_to_live(ttl, dt))
                               : 1.0;
      const double from = static_cast<double>(it->second.tick), now = static_cast<double>(tick);
      // Kept a second of sim time past its last tick: the pages draw states older than this one
      // (their frames lag, and the wrenches overtake the states on the way, server.hpp) and
      // expire each wrench at its own tick. (A wrench may be accepted a little ahead of the
      // newest state; far ahead: the tick went back, rigidd was reset or restarted.)
      const double grace = dt > 0 ? 1 / dt : 1;
      const bool expired = now > from + ticks + grace || now + 100 + ticks < from;
      if (expired) {
        it = wrenches_.erase(it);
        wrenches_changed_ = true;
      } else {
        ++it;
      }
    }
    if (!wrenches_changed_) return std::nullopt;
    wrenches_changed_ = false;
    std::vector<AcceptedCommand> out;
    out.reserve(wrenches_.size());
    for (const auto& [key, a] : wrenches_)
      out.push_back(a);
    std::sort(out.begin(), out.end(), [](const auto& x, const auto& y) { return x.tick < y.tick; });
    return out;
  }

  std::vector<view::Bytes> greeting() {
    const std::lock_guard lock(mutex_);
    std::vector<view::Bytes> out;
    if (scene_text_) out.push_back(scene_text_);
    if (stats_text_) out.push_back(stats_text_);
    if (wrenches_text_) out.push_back(wrenches_text_);  // a page that opens while they act
    return out;
  }

  // Server thread.
  void command(std::uint64_t page, const view::PageCommand& c,
               std::function<void(view::Bytes)> reply) {
    if (c.op == view::Op::kPush) return push(page, c);
    if (c.op == view::Op::kWatch) return watch(page, c.body);
    {
      const std::lock_guard lock(mutex_);
      if (jobs_.size() < kMaxPendingControls) {
        jobs_.push_back(Job{c, std::move(reply)});
        wake_.notify_all();
        return;
      }
    }
    reply(std::make_shared<const std::string>(view::reply_json(
        c.id, view::op_name(c.op), false, "refused", 0, "busy: too many requests waiting")));
  }

  // A page's watched body (body -1: none), until kWatchLifetime from now: the page re-sends it
  // while it holds, and a page that goes away stops doing so.
  void watch(std::uint64_t page, std::int32_t body) {
    const std::lock_guard lock(mutex_);
    if (body < 0) {
      watches_.erase(page);
      return;
    }
    const auto until = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                          std::chrono::duration<double>(view::kWatchLifetime));
    if (!watches_.contains(page) && watches_.size() >= view::kMaxWatched) {
      auto soonest = watches_.begin();  // full: the watch that lapses first makes room
      for (auto it = watches_.begin(); it != watches_.end(); ++it)
        if (it->second.until < soonest->second.until) soonest = it;
      watches_.erase(soonest);
    }
    watches_[page] = Watch{body, until};
  }

  // Pump thread, mutex held: the bodies the pages watch, each once, forgetting lapsed watches.
  std::vector<std::int32_t> watched_bodies() {
    const auto now = Clock::now();
    std::vector<std::int32_t> out;
    for (auto it = watches_.begin(); it != watches_.end();) {
      if (it->second.until < now) {
        it = watches_.erase(it);
        continue;
      }
      if (std::find(out.begin(), out.end(), it->second.body) == out.end())
        out.push_back(it->second.body);
      ++it;
    }
    return out;
  }

  void push(std::uint64_t page, const view::PageCommand& c) {
    const auto now = Clock::now();
    auto it = last_push_.find(page);
    if (it != last_push_.end() && now - it->second < kMinPushInterval) return;  // too often
    if (it == last_push_.end() && last_push_.size() >= kMaxPushingPages) last_push_.clear();
    last_push_[page] = now;
    {
      // The push acts from the tick rigidd accepts it at; the accepted stream says which, but may
      // come after the states it acted on: the newest state's tick is a lower bound for it.
      const std::lock_guard lock(mutex_);
      if (latest_ && drives_.size() < kMaxPendingDrives)
        drives_.push_back(Drive{c.body, latest_->tick, c.ttl > 0 ? c.ttl : kPushTtl});
    }
    WrenchCommand w;
    w.key = static_cast<std::int32_t>(page & 0x7fffffff);  // one wrench per page and body
    w.body_id = c.body;
    w.force = c.force;
    w.point = c.point;
    w.force_frame = Frame::kWorld;
    w.ttl = c.ttl > 0 ? c.ttl : kPushTtl;  // a Foxglove client's push: its duration
    session_.send(w);
  }

  void work() {
    std::unique_lock lock(mutex_);
    while (true) {
      wake_.wait(lock, [this] { return stopping_ || !jobs_.empty(); });
      if (stopping_) return;
      Job job = std::move(jobs_.front());
      jobs_.pop_front();
      lock.unlock();
      const view::PageCommand& c = job.command;
      std::optional<ControlReply> r;
      switch (c.op) {
        case view::Op::kPause:
          r = session_.pause(kControlPatience);
          break;
        case view::Op::kResume:
          r = session_.resume(kControlPatience);
          break;
        case view::Op::kStep:
          r = session_.step(c.steps, kControlPatience);
          break;
        case view::Op::kReset:
          r = session_.reset(kControlPatience);
          break;
        case view::Op::kSetState:
          r = session_.set_state(c.body, c.state, kControlPatience);
          break;
        case view::Op::kResetBody:
          r = session_.reset_body(c.body, kControlPatience);
          break;
        case view::Op::kPush:
        case view::Op::kPlay:  // playback only: refused by the server in live mode
        case view::Op::kSeek:
        case view::Op::kSpeed:
        case view::Op::kWatch:  // (command() keeps it)
          break;
      }
      const std::string text =
          r ? view::reply_json(c.id, view::op_name(c.op), r->outcome == Outcome::kOk,
                               client::outcome_name(r->outcome), r->tick, r->message)
            : view::reply_json(c.id, view::op_name(c.op), false, "timeout", 0,
                               "no answer from rigidd within 3 s");
      job.reply(std::make_shared<const std::string>(text));
      lock.lock();
    }
  }

  void pump() {
    const auto period = std::chrono::duration_cast<Clock::duration>(
        std::chrono::duration<double>(1.0 / kFrameRate));
    const auto wrench_period = std::chrono::duration_cast<Clock::duration>(
        std::chrono::duration<double>(1.0 / view::kWrenchRate));
    auto earliest = Clock::now();  // the next state frame goes out no sooner (kFrameRate)
    std::unique_lock lock(mutex_);
    while (!stopping_) {
      // A state goes out when it arrives, at most kFrameRate times a second: sending the newest
      // at fixed 60 Hz slots instead made it wait half a period on average for the next one.
      if (fresh_state_.wait_until(lock, earliest, [this] { return stopping_; })) return;
      fresh_state_.wait_for(lock, period, [this] { return stopping_ || fresh_; });
      if (stopping_) return;
      // A SceneInfo that came before the handler was set (DDS: transient-local, at discovery),
      // or a restarted rigidd's.
      if (const auto g = session_.scene_generation(); g != seen_generation_) {
        lock.unlock();
        if (const auto d = session_.wait_scene(0ms)) set_scene(*d);
        seen_generation_ = g;
        lock.lock();
      }
      if (!fresh_ || !latest_) continue;
      fresh_ = false;
      earliest = Clock::now() + period;
      const StateFrame state = *latest_;
      const auto generation = static_cast<std::uint32_t>(generation_);
      if (generation_ != drift_generation_ && scene_) {
        drift_.set_scene(*scene_);
        drift_generation_ = generation_;
      }
      for (const Drive& d : drives_)
        drift_.drive(d.body, d.tick, d.ttl);
      drives_.clear();
      std::optional<std::vector<AcceptedCommand>> wrenches;
      if (Clock::now() >= next_wrenches_) {
        wrenches = acting_wrenches(state.tick);
        if (wrenches) next_wrenches_ = Clock::now() + wrench_period;
      }
      view::Bytes wrenches_text;
      if (wrenches) {
        wrenches_text = std::make_shared<const std::string>(view::wrenches_json(*wrenches));
        wrenches_text_ = wrenches_text;
      }
      const std::vector<std::int32_t> watched = watched_bodies();
      lock.unlock();
      drift_.update(state);
      // Large scenes: poses, the worst drifts and the watched bodies' whole states (protocol.hpp).
      server_->broadcast_state(std::make_shared<const std::string>(
          view::state_in_float32(state.ids.size())
              ? view::encode_pose_state(state, generation, drift_.energy(), drift_.momentum(),
                                        watched)
              : view::encode_state(state, generation, drift_.energy(), drift_.momentum())));
      if (wrenches_text) server_->broadcast_text(std::move(wrenches_text));
      lock.lock();
      for (const Channel c : {Channel::kTransforms, Channel::kBodyStates, Channel::kState})
        if (server_->foxglove_subscribed(c))
          server_->broadcast_foxglove(c, foxglove_state(c, state));
    }
  }

  client::Session& session_;
  std::unique_ptr<view::ViewServer> server_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::condition_variable fresh_state_;  // the pump's: a state arrived, or stopping
  std::optional<StateFrame> latest_;
  bool fresh_ = false;
  std::optional<SceneDescription> scene_;
  std::uint64_t generation_ = 0;
  std::uint64_t seen_generation_ = 0;  // pump thread only
  view::Bytes scene_text_, stats_text_, wrenches_text_;
  std::optional<StatsReport> stats_;
  // Foxglove: the bodies' names by id (scene), and those of the newest state's bodies in order.
  clients::BodyNames names_;
  std::vector<std::int32_t> name_ids_;
  std::vector<std::string> state_names_;
  std::uint64_t names_generation_ = 0;
  std::deque<Job> jobs_;
  bool stopping_ = false;
  std::map<std::uint64_t, Clock::time_point> last_push_;  // server thread only
  // (source, body, key): a wrench replaces the previous one with the same key in rigidd's table.
  using WrenchKey = std::tuple<std::int64_t, std::int32_t, std::int32_t>;
  std::map<WrenchKey, AcceptedCommand> wrenches_;
  bool wrenches_changed_ = false;
  Clock::time_point next_wrenches_{};  // pump thread only
  // Each body's drift since its reference (drift.hpp), kept by the pump thread from the states it
  // sends; the wrenches that restart a body's reference come from the bus and server threads.
  struct Drive {
    std::int32_t body;
    std::int64_t tick;
    double ttl;
  };
  std::vector<Drive> drives_;
  struct Watch {
    std::int32_t body;
    Clock::time_point until;
  };
  std::map<std::uint64_t, Watch> watches_;  // by page
  view::DriftTracker drift_;                // pump thread only
  std::uint64_t drift_generation_ = 0;      // pump thread only
  std::thread pump_, worker_;
};

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string_view> args(argv + 1, argv + argc);
  view::ViewOptions options;
  try {
    options = view::parse_options(args);
  } catch (const clients::UsageError& e) {
    std::cerr << "rigid-view: " << e.what() << '\n';
    return clients::kExitUsage;
  }
  if (options.help) {
    std::cout << view::usage();
    return clients::kExitOk;
  }
  if (!options.file.empty()) {  // rigid-view FILE: a recording instead of the bus
    return view::serve_recording(options, options.web_dir.empty()
                                              ? default_web_dir()
                                              : std::filesystem::path(options.web_dir));
  }
  const clients::DdsLog dds_log;  // before the bus: Cyclone's lines are told in our words
  try {
    util::SignalWatcher signals({SIGINT, SIGTERM});
    std::optional<client::Session> joined;
    try {
      joined.emplace(options.bus);
    } catch (const client::BusError& e) {
      std::cerr << "rigid-view: " << clients::bus_error_line(e.what(), options.bus, dds_log)
                << '\n';
      return clients::kExitFailed;
    }
    client::Session& session = *joined;
    Viewer viewer(options, session);
    viewer.start();
    if (viewer.listens_beyond_host()) {
      std::cerr << "rigid-view: warning: listening on " << options.host
                << (viewer.address() == options.host ? "" : " (" + viewer.address() + ")")
                << ": any host that reaches this one can open the page"
                << (options.read_only ? "" : " and pause, step, reset and push the simulation")
                << " (no authentication; use 127.0.0.1 and an SSH tunnel, or --read-only)\n";
    }
    std::cout << "rigid-view: http://" << view::url_host(options.host) << ':' << viewer.port()
              << "/ (" << client::describe(options.bus) << (options.read_only ? ", read-only" : "")
              << ")" << std::endl;
    // A failed DDS Security handshake is told once (Cyclone repeats it every second), in one line.
    std::string told;
    while (!signals.wait(1s)) {
      const auto failure = dds_log.security_failure();
      if (failure && failure->handshake && failure->reason != told) {
        std::cerr << "rigid-view: DDS Security authentication with a participant failed: "
                  << failure->reason << " (rigidd and this identity must come from one keystore)\n";
        told = failure->reason;
      }
    }
    viewer.stop();
    std::cerr << "rigid-view: " << view::describe(viewer.counts()) << '\n';
    return clients::kExitOk;
  } catch (const std::exception& e) {
    std::cerr << "rigid-view: " << e.what() << '\n';
    return clients::kExitFailed;
  }
}
