#include "playback_viewer.hpp"

#include <signal.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <deque>
#include <exception>
#include <filesystem>
#include <functional>
#include <iostream>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "playback_clock.hpp"
#include "protocol.hpp"
#include "recording_source.hpp"
#include "server.hpp"
#include "util/signal_watcher.hpp"

namespace rigid::view {
namespace {

using namespace std::chrono_literals;
using Clock = PlaybackClock::Clock;

constexpr double kFrameRate = 60;      // as live: the page never needs more
constexpr auto kStatusPeriod = 250ms;  // the timeline's position while playing
// States a page may still draw when a newer one's wrenches reach it (wrenches_for).
constexpr std::size_t kRecentStates = ViewServer::kMaxUnackedStates + 2;

// The file's name as the page shows it: JSON text must be UTF-8, so bytes beyond ASCII become '?'.
std::string display_name(const std::string& path) {
  std::string name = std::filesystem::path(path).filename().string();
  for (char& c : name)
    if (static_cast<unsigned char>(c) >= 0x80) c = '?';
  return name;
}

class RecordingViewer {
 public:
  RecordingViewer(const ViewOptions& o, const std::filesystem::path& web_dir, Recording recording)
      : recording_(std::move(recording)),
        clock_(recording_.states),
        name_(display_name(recording_.path)) {
    ServerOptions so;
    so.host = o.host;
    so.port = o.port;
    so.read_only = o.read_only;
    so.web_dir = web_dir;
    so.playback = true;
    server_ = std::make_unique<ViewServer>(
        so,
        [this](std::uint64_t, const PageCommand& c, std::function<void(Bytes)> reply) {
          command(c, std::move(reply));
        },
        [this] { return greeting(); });
  }

  std::uint16_t port() const { return server_->port(); }
  std::string address() const { return server_->address(); }
  bool listens_beyond_host() const { return server_->listens_beyond_host(); }
  const ServerCounts& counts() const { return server_->counts(); }

  void start() {
    server_->start();
    pump_ = std::thread([this] { pump(); });
  }

  void stop() {
    {
      const std::lock_guard lock(mutex_);
      stopping_ = true;
    }
    wake_.notify_all();
    if (pump_.joinable()) pump_.join();
    server_->stop();
  }

 private:
  // Server thread: a command valid in playback (the server refused the others).
  void command(const PageCommand& c, const std::function<void(Bytes)>& reply) {
    std::string message;
    std::int64_t tick = 0;
    {
      const std::lock_guard lock(mutex_);
      const auto now = Clock::now();
      switch (c.op) {
        case Op::kPlay:
          clock_.play(now);
          break;
        case Op::kPause:
          clock_.pause(now);
          break;
        case Op::kSeek:
          if (c.time) {
            clock_.seek_time(*c.time, now);
          } else {
            clock_.seek_tick(c.tick, now);
          }
          break;
        case Op::kSpeed:
          clock_.set_speed(c.speed, now);
          break;
        default:
          return;  // refused by the server in playback (refusal_in_mode)
      }
      const RecordedState& s = recording_.states[clock_.current(now)];
      tick = s.tick;
      char line[96];
      std::snprintf(line, sizeof line, "t = %.6f s, %s at %gx", s.sim_time,
                    clock_.playing() ? "playing" : "paused", clock_.speed());
      message = line;
      changed_ = true;  // the pump sends the state and the timeline's status at once
    }
    wake_.notify_all();
    reply(std::make_shared<const std::string>(
        reply_json(c.id, op_name(c.op), true, "ok", tick, message)));
  }

  // Server thread: the scene in force and where the timeline is (the pump then sends the state).
  std::vector<Bytes> greeting() {
    const std::lock_guard lock(mutex_);
    changed_ = true;  // the new page needs the state shown, even while paused
    wake_.notify_all();
    const std::size_t i = clock_.current(Clock::now());
    std::vector<Bytes> out{scene_text(recording_.states[i].scene), status_text(i, Clock::now())};
    if (Bytes stats = recording_.stats_at(i)) out.push_back(std::move(stats));
    // The arrows of the state the pump sent last (the page's first state is that one, or a newer
    // one with its own arrows before it).
    if (!sent_wrenches_.empty()) out.push_back(wrenches_text(sent_wrenches_));
    return out;
  }

  // Mutex held, state i about to be sent: the wrenches acting on it and on the last states sent
  // before it in its stretch. Texts overtake states on their way to a page (server.hpp), which
  // may still be drawing one of those (at most kMaxUnackedStates behind, and one waiting): the
  // page draws each wrench with the states whose ticks it acts on (unique within a stretch), so
  // that an arrow neither ends early nor starts before its state arrives.
  std::vector<std::size_t> wrenches_for(std::size_t i) {
    if (recent_.empty() || recent_.back() != i) recent_.push_back(i);
    if (recent_.size() > kRecentStates) recent_.pop_front();
    std::vector<std::size_t> out;
    for (const std::size_t j : recent_) {
      if (recording_.states[j].stretch != recording_.states[i].stretch) continue;
      const std::vector<std::size_t> acting = recording_.wrenches_at(j);
      out.insert(out.end(), acting.begin(), acting.end());
    }
    // By (stretch, tick): wrenches.all()'s order; the newest kMaxWrenchesShown.
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    if (out.size() > kMaxWrenchesShown)
      out.erase(out.begin(), out.end() - static_cast<std::ptrdiff_t>(kMaxWrenchesShown));
    return out;
  }

  // The recorded wrenches acting on a state, as live mode sends them (with the tick each stops,
  // when a newer wrench or a reset cut it short).
  Bytes wrenches_text(const std::vector<std::size_t>& indices) const {
    std::vector<AcceptedCommand> shown;
    std::vector<std::int64_t> until;
    shown.reserve(indices.size());
    until.reserve(indices.size());
    for (const std::size_t k : indices) {
      const RecordedWrench& w = recording_.wrenches.all()[k];
      shown.push_back(w.command);
      until.push_back(w.until);
    }
    return std::make_shared<const std::string>(wrenches_json(shown, until));
  }

  Bytes scene_text(std::uint32_t scene) const {
    return std::make_shared<const std::string>(
        scene_json(recording_.scenes[scene], Recording::generation(scene)));
  }

  Bytes status_text(std::size_t i, Clock::time_point now) const {
    const RecordedState& s = recording_.states[i];
    PlaybackStatus st;
    st.file = name_;
    st.playing = clock_.playing();
    st.speed = clock_.speed();
    st.start = clock_.start();
    st.end = clock_.end();
    st.position = clock_.playing() ? clock_.position(now) : s.position;
    st.tick = s.tick;
    st.sim_time = s.sim_time;
    st.index = i;
    st.states = recording_.states.size();
    return std::make_shared<const std::string>(playback_json(st));
  }

  void pump() {
    const auto period = std::chrono::duration_cast<Clock::duration>(
        std::chrono::duration<double>(1.0 / kFrameRate));
    auto next = Clock::now();
    auto next_status = next;
    std::optional<std::size_t> sent;
    std::optional<std::uint32_t> sent_scene;
    Bytes sent_stats;
    bool was_playing = false;
    std::unique_lock lock(mutex_);
    while (!stopping_) {
      next += period;
      wake_.wait_until(lock, next, [this] { return stopping_ || changed_; });
      if (stopping_) return;
      const auto now = Clock::now();
      if (now > next + 10 * period) next = now;  // after a stall: no burst
      const std::size_t i = clock_.current(now);
      const bool changed = changed_ || i != sent || clock_.playing() != was_playing;
      const bool status_due = changed || (clock_.playing() && now >= next_status);
      changed_ = false;
      was_playing = clock_.playing();
      if (!status_due) continue;
      const std::uint32_t scene = recording_.states[i].scene;
      Bytes scene_changed = scene != sent_scene ? scene_text(scene) : nullptr;
      const Bytes status = status_text(i, now);
      const Bytes frame = changed ? recording_.frames[i] : nullptr;
      // The arrows of the state shown, sent when they differ from the last ones.
      Bytes wrenches;
      if (changed) {
        std::vector<std::size_t> acting = wrenches_for(i);
        if (acting != sent_wrenches_) {
          wrenches = wrenches_text(acting);
          sent_wrenches_ = std::move(acting);
        }
      }
      Bytes stats = recording_.stats_at(i);  // the HUD's Stats as recorded at that time
      if (stats == sent_stats) {
        stats = nullptr;
      } else {
        sent_stats = stats;
      }
      sent = i;
      sent_scene = scene;
      next_status = now + kStatusPeriod;
      lock.unlock();
      if (scene_changed) server_->broadcast_text(std::move(scene_changed));
      server_->broadcast_text(status);
      if (stats) server_->broadcast_text(std::move(stats));
      if (wrenches) server_->broadcast_text(std::move(wrenches));
      if (frame) server_->broadcast_state(frame);
      lock.lock();
    }
  }

  const Recording recording_;
  PlaybackClock clock_;  // guarded by mutex_
  const std::string name_;
  std::unique_ptr<ViewServer> server_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool changed_ = true;
  bool stopping_ = false;
  // Guarded by mutex_: the wrenches last sent (indices into wrenches.all()), the states last sent.
  std::vector<std::size_t> sent_wrenches_;
  std::deque<std::size_t> recent_;
  std::thread pump_;
};

}  // namespace

int serve_recording(const ViewOptions& options, const std::filesystem::path& web_dir) {
  try {
    util::SignalWatcher signals({SIGINT, SIGTERM});  // before any thread: they inherit the mask
    LoadLimits limits;
    limits.lcm_prefix = options.bus.prefix;
    limits.lcm_prefix_given = options.prefix_given;
    limits.max_bytes = static_cast<std::size_t>(options.max_memory_mib) << 20;
    const auto started = Clock::now();
    Recording recording = load_recording(options.file, limits);
    const double load_s = std::chrono::duration<double>(Clock::now() - started).count();
    if (!recording.note.empty())
      std::cerr << "rigid-view: " << options.file << ": " << recording.note << '\n';
    char summary[200];
    std::snprintf(summary, sizeof summary,
                  "%zu states, t = %.3f to %.3f s, ticks %lld to %lld, %zu scene(s), %.1f MiB in "
                  "memory, read in %.2f s",
                  recording.states.size(), recording.states.front().sim_time,
                  recording.states.back().sim_time,
                  static_cast<long long>(recording.states.front().tick),
                  static_cast<long long>(recording.states.back().tick), recording.scenes.size(),
                  static_cast<double>(recording.bytes) / (1 << 20), load_s);
    const std::string kind = recording.kind;
    RecordingViewer viewer(options, web_dir, std::move(recording));
    viewer.start();
    if (viewer.listens_beyond_host()) {
      std::cerr << "rigid-view: warning: listening on " << options.host
                << (viewer.address() == options.host ? "" : " (" + viewer.address() + ")")
                << ": any host that reaches this one can open the page (no authentication; use "
                   "127.0.0.1 and an SSH tunnel)\n";
    }
    std::cout << "rigid-view: http://" << url_host(options.host) << ':' << viewer.port()
              << "/ (playing " << options.file << ", " << kind << ": " << summary
              << (options.read_only ? "; read-only" : "") << ")" << std::endl;
    while (!signals.wait(1s)) {
    }
    viewer.stop();
    std::cerr << "rigid-view: " << describe(viewer.counts()) << '\n';
    return clients::kExitOk;
  } catch (const std::exception& e) {
    std::cerr << "rigid-view: " << e.what() << '\n';
    return clients::kExitFailed;
  }
}

}  // namespace rigid::view
