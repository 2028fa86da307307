#include "ctl/ctl_run.hpp"

#include <unistd.h>

#include <cmath>
#include <condition_variable>
#include <cstdarg>
#include <cstdio>
#include <deque>
#include <mutex>
#include <ostream>
#include <utility>

#include "cli/dds_log.hpp"
#include "cli/state_rows.hpp"
#include "ctl/push_request.hpp"
#include "rigid/client/names.hpp"
#include "rigid/client/session.hpp"
#include "util/state_csv.hpp"

namespace rigid::ctl {
namespace {

using namespace std::chrono_literals;
using client::Session;
using clients::kExitFailed;
using clients::kExitOk;
using clients::kExitTimeout;
using rigid::ControlKind;

// The shape's name, "-" for none (a column of rigidctl bodies).
std::string shape_or_dash(rigid::ShapeKind k) {
  const std::string_view name = client::shape_name(k);
  return name.empty() ? "-" : std::string(name);
}

[[gnu::format(printf, 1, 2)]] std::string fmt(const char* format, ...) {
  char buffer[512];
  va_list args;
  va_start(args, format);
  std::vsnprintf(buffer, sizeof buffer, format, args);
  va_end(args);
  return buffer;
}

std::string no_answer(const CtlOptions& o, const clients::DdsLog& log, const std::string& what) {
  return "rigidctl: no " + what + " from rigidd within " +
         fmt("%.3g", static_cast<double>(o.timeout.count()) / 1000.0) + " s on " +
         client::describe(o.bus) + clients::no_rigidd_hint(o.bus, log);
}

int bodies(const CtlOptions& o, Session& session, const clients::DdsLog& log, std::ostream& out,
           std::ostream& err) {
  const auto scene = session.wait_scene(o.timeout);
  if (!scene) {
    err << no_answer(o, log, "SceneInfo") << '\n';
    return kExitTimeout;
  }
  const rigid::SceneDescription& s = *scene;
  out << "scene " << s.scene_name << '\n'
      << fmt("tick %.6g s (%.6g Hz), %d substep(s), state every %d tick(s), integrator %s\n", s.dt,
             1.0 / s.dt, s.substeps, s.publish_every, s.integrator.c_str())
      << fmt("gravity (%g, %g, %g) m/s^2, limits: force %g N, torque %g N m\n", s.gravity[0],
             s.gravity[1], s.gravity[2], s.max_force, s.max_torque);
  out << fmt("%4s  %-16s %10s  %10s %10s %10s  %-9s %s\n", "id", "name", "mass kg", "Ixx", "Iyy",
             "Izz", "shape", "dims m");
  for (std::size_t i = 0; i < s.body_count(); ++i) {
    const double* I = &s.inertia[6 * i];
    const double* d = &s.shape_dims[3 * i];
    out << fmt("%4d  %-16s %10.4g  %10.4g %10.4g %10.4g  %-9s", s.ids[i], s.names[i].c_str(),
               s.masses[i], I[0], I[1], I[2], shape_or_dash(s.shape_kinds[i]).c_str());
    if (s.shape_kinds[i] != rigid::ShapeKind::kNone) out << fmt(" %g %g %g", d[0], d[1], d[2]);
    out << '\n';
  }
  return kExitOk;
}

// set BODY ..., reset BODY: an edit, answered like a control.
int edit(const CtlOptions& o, Session& session, const clients::DdsLog& log, std::ostream& out,
         std::ostream& err) {
  const std::string_view what = o.command == Command::kSet ? "set" : "reset";
  const auto scene = session.wait_scene(o.timeout);
  if (!scene) {
    err << no_answer(o, log, "SceneInfo") << '\n';
    return kExitTimeout;
  }
  const auto body = client::find_body(*scene, o.body);
  if (!body) {
    // Refused here as rigidd would refuse it, with its exit status (1), as push does.
    err << "rigidctl: " << what << ": refused: no body " << clients::quoted(o.body)
        << " in the scene (bodies: " << client::body_list(*scene) << ")\n";
    return kExitFailed;
  }
  std::optional<rigid::ControlReply> reply;
  if (o.command == Command::kSet) {
    rigid::StateEdit s;
    if (o.position) {
      s.set |= rigid::kSetPosition;
      s.position = *o.position;
    }
    if (o.orientation) {
      s.set |= rigid::kSetOrientation;
      s.orientation = *o.orientation;
    }
    if (o.velocity) {
      s.set |= rigid::kSetLinearVelocity;
      s.linear_velocity = *o.velocity;
      s.velocity_frame = o.frame;
    }
    if (o.angular_velocity) {
      s.set |= rigid::kSetAngularVelocity;
      s.angular_velocity = *o.angular_velocity;
      s.angular_velocity_frame = o.frame;
    }
    reply = session.set_state(*body, s, o.timeout);
  } else {
    reply = session.reset_body(*body, o.timeout);
  }
  if (!reply) {
    err << no_answer(o, log, "reply to " + std::string(what)) << '\n';
    return kExitTimeout;
  }
  if (reply->outcome != rigid::Outcome::kOk) {
    err << "rigidctl: " << what << ": " << client::outcome_name(reply->outcome) << ": "
        << reply->message << '\n';
    return kExitFailed;
  }
  out << what << ": ok at tick " << reply->tick << " on " << o.body << " (id " << *body << ")\n";
  return kExitOk;
}

int control(const CtlOptions& o, Session& session, const clients::DdsLog& log, std::ostream& out,
            std::ostream& err) {
  rigid::ControlCommand c;
  switch (o.command) {
    case Command::kPause:
      c.command = ControlKind::kPause;
      break;
    case Command::kResume:
      c.command = ControlKind::kResume;
      break;
    case Command::kStep:
      c.command = ControlKind::kStep;
      c.steps = o.steps;
      break;
    case Command::kReset:
      c.command = ControlKind::kReset;
      break;
    default:
      c.command = ControlKind::kSetRtf;
      c.rtf = o.rtf;
      break;
  }
  const auto reply = session.request(c, o.timeout);
  if (!reply) {
    err << no_answer(o, log, "reply to " + std::string(client::control_name(c.command))) << '\n';
    return kExitTimeout;
  }
  if (reply->outcome != rigid::Outcome::kOk) {
    err << "rigidctl: " << client::control_name(c.command) << ": "
        << client::outcome_name(reply->outcome) << ": " << reply->message << '\n';
    return kExitFailed;
  }
  out << client::control_name(c.command) << ": ok at tick " << reply->tick << '\n';
  return kExitOk;
}

int push(const CtlOptions& o, Session& session, const clients::DdsLog& log, std::ostream& out,
         std::ostream& err) {
  const auto scene = session.wait_scene(o.timeout);
  if (!scene) {
    err << no_answer(o, log, "SceneInfo") << '\n';
    return kExitTimeout;
  }
  // What rigidd would refuse is refused here, before sending, with its exit status (1).
  const auto body = client::find_body(*scene, o.body);
  if (!body) {
    err << "rigidctl: push: refused: no body " << clients::quoted(o.body)
        << " in the scene (bodies: " << client::body_list(*scene) << ")\n";
    return kExitFailed;
  }
  const PushRequest request = make_push(o, *scene, *body);
  if (!request.refusal.empty()) {
    err << "rigidctl: push: refused: " << request.refusal << '\n';
    return kExitFailed;
  }
  std::string refused;
  const auto accepted = session.push(request.wrench, o.timeout, &refused);
  if (!accepted && !refused.empty()) {
    err << "rigidctl: push: refused by rigidd: " << refused << '\n';
    return kExitFailed;
  }
  if (!accepted) {
    err << "rigidctl: push: rigidd did not accept the wrench within "
        << fmt("%.3g", static_cast<double>(o.timeout.count()) / 1000.0) << " s on "
        << client::describe(o.bus)
        << ": it refused it (rigidd's log and 'rigidctl stats' say why) or is not running\n";
    return kExitTimeout;
  }
  out << "push: accepted at tick " << accepted->tick << " on " << o.body << " (id " << *body << ") "
      << push_summary(request, o, *scene) << '\n';
  return kExitOk;
}

// Clears the session's state and Stats handlers when the command that set them returns: they
// refer to its locals, which the transport's thread would otherwise go on calling into after they
// are gone (the session outlives the command). Declared after those locals, so it runs first.
class HandlerScope {
 public:
  explicit HandlerScope(Session& session) : session_(session) {}
  ~HandlerScope() {
    session_.on_each_state({});
    session_.on_each_stats({});
  }
  HandlerScope(const HandlerScope&) = delete;
  HandlerScope& operator=(const HandlerScope&) = delete;

 private:
  Session& session_;
};

// States from the transport's thread to the main thread, which prints them.
class StateQueue {
 public:
  void push(const rigid::StateFrame& s) {
    {
      const std::lock_guard lock(mutex_);
      if (queue_.size() >= kMax) queue_.pop_front();  // a terminal slower than the bus
      queue_.push_back(s);
    }
    changed_.notify_one();
  }
  // Waits up to `patience` for states; takes them all.
  std::deque<rigid::StateFrame> take(std::chrono::milliseconds patience) {
    std::unique_lock lock(mutex_);
    changed_.wait_for(lock, patience, [&] { return !queue_.empty(); });
    return std::exchange(queue_, {});
  }

 private:
  static constexpr std::size_t kMax = 10000;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<rigid::StateFrame> queue_;
};

void print_table(const rigid::StateFrame& f, const rigid::SceneDescription& scene,
                 const std::vector<bool>& only, bool tty, std::ostream& out) {
  if (tty) out << "\x1b[H\x1b[2J";  // redraw in place, like watch(1)
  out << fmt("tick %lld  t = %.3f s\n", static_cast<long long>(f.tick), f.sim_time);
  out << fmt("%-16s %10s %10s %10s  %8s %8s %8s %8s  %10s %10s\n", "body", "x m", "y m", "z m",
             "qw", "qx", "qy", "qz", "|v| m/s", "|w| rad/s");
  const clients::BodyNames names(scene);
  for (std::size_t i = 0; i < f.body_count(); ++i) {
    if (!only.empty() && !only[i]) continue;
    const double* p = &f.position[3 * i];
    const double* q = &f.orientation[4 * i];
    const double* v = &f.linear_velocity[3 * i];
    const double* w = &f.angular_velocity[3 * i];
    out << fmt("%-16s %10.4f %10.4f %10.4f  %8.5f %8.5f %8.5f %8.5f  %10.4g %10.4g\n",
               names.name(f.ids[i]).c_str(), p[0], p[1], p[2], q[0], q[1], q[2], q[3],
               std::hypot(v[0], v[1], v[2]), std::hypot(w[0], w[1], w[2]));
  }
  if (!tty) out << '\n';
  out.flush();
}

// Which bodies echo prints, by their index in the state (ids in scene order); empty: all. False
// (and the reason on err) if one of them is not in the scene.
bool select_bodies(const CtlOptions& o, const rigid::SceneDescription& scene,
                   std::vector<bool>& only, std::ostream& err) {
  only.clear();
  if (o.bodies.empty()) return true;
  only.assign(scene.body_count(), false);
  for (const std::string& b : o.bodies) {
    const auto id = client::find_body(scene, b);
    if (!id) {
      err << "rigidctl: echo: no body " << clients::quoted(b)
          << " in the scene (bodies: " << client::body_list(scene) << ")\n";
      return false;
    }
    for (std::size_t i = 0; i < scene.ids.size(); ++i)
      if (scene.ids[i] == *id) only[i] = true;
  }
  return true;
}

int echo(const CtlOptions& o, Session& session, const clients::DdsLog& log,
         util::SignalWatcher& signals, std::ostream& out, std::ostream& err) {
  StateQueue queue;
  const HandlerScope handlers(session);
  session.on_each_state([&](const rigid::StateFrame& s) { queue.push(s); });
  std::uint64_t generation = session.scene_generation();
  auto scene = session.wait_scene(o.timeout);
  if (!scene) {
    err << no_answer(o, log, "SceneInfo") << '\n';
    return kExitTimeout;
  }
  std::vector<bool> only;
  if (!select_bodies(o, *scene, only, err)) return clients::kExitUsage;
  const bool tty = ::isatty(STDOUT_FILENO) == 1;
  clients::BodyNames names(*scene);
  const double rate = o.rate_hz.value_or(o.csv ? 0.0 : 10.0);  // 0: every state
  const auto period =
      std::chrono::nanoseconds(rate > 0 ? static_cast<std::int64_t>(1e9 / rate) : 0);
  auto next_output = std::chrono::steady_clock::now();
  auto last_state = std::chrono::steady_clock::now();
  std::int64_t printed = 0;
  std::string text;
  if (o.csv) out << util::kStateCsvHeader;
  while (!o.count || printed < *o.count) {
    if (signals.wait(0ms)) break;
    auto states = queue.take(100ms);
    // A restarted rigidd may run another scene: name and select its bodies from the new one.
    if (session.scene_generation() != generation) {
      generation = session.scene_generation();
      scene = session.wait_scene(0ms);
      names = clients::BodyNames(*scene);
      if (!select_bodies(o, *scene, only, err)) return kExitFailed;
    }
    const auto now = std::chrono::steady_clock::now();
    if (states.empty()) {
      if (now - last_state > o.timeout) {
        err << no_answer(o, log, "state") << '\n';
        return kExitTimeout;
      }
      continue;
    }
    last_state = now;
    if (period.count() > 0) {
      if (now < next_output) continue;
      next_output = now + period;
      states.erase(states.begin(), states.end() - 1);  // the newest only
    }
    for (const rigid::StateFrame& s : states) {
      // Not this scene's (a new rigidd whose SceneInfo has not arrived yet): names would be wrong.
      if (s.ids != scene->ids) continue;
      if (o.csv) {
        text.clear();
        clients::append_frame_rows(s, names, text, only);
        out << text;
        out.flush();
      } else {
        print_table(s, *scene, only, tty, out);
      }
      if (o.count && ++printed >= *o.count) break;
    }
  }
  return kExitOk;
}

void print_stats(const rigid::StatsReport& s, std::ostream& out) {
  const rigid::RejectCounts& r = s.rejected;
  const std::int64_t refused = r.non_finite + r.unknown_body + r.over_limit + r.undecodable +
                               r.stale_sequence + r.queue_full + r.invalid + r.over_share +
                               r.rate_limited + r.not_permitted;
  out << fmt("tick %lld  t = %.3f s  %s%s  rtf %.4f (since start %.4f)\n",
             static_cast<long long>(s.tick), s.sim_time,
             std::string(rigid::mode_name(s.mode)).c_str(), s.paused ? " paused" : "",
             s.rtf_last_second, s.rtf_since_start)
      << fmt("  lateness us: p50 %.1f  p99 %.1f  max %.1f   overruns %lld\n", s.lateness_p50_us,
             s.lateness_p99_us, s.lateness_max_us, static_cast<long long>(s.overruns))
      << fmt("  step cost us: p50 %.1f  max %.1f   states skipped %lld\n", s.step_cost_p50_us,
             s.step_cost_max_us, static_cast<long long>(s.states_skipped))
      << fmt("  physics: bodies frozen %lld, large-rotation steps %lld\n",
             static_cast<long long>(s.bodies_frozen),
             static_cast<long long>(s.large_rotation_steps))
      << fmt("  commands: accepted %lld, refused %lld (non_finite %lld, unknown_body %lld, "
             "over_limit %lld, undecodable %lld, stale_sequence %lld, queue_full %lld, invalid "
             "%lld, over_share %lld, rate_limited %lld, not_permitted %lld)\n",
             static_cast<long long>(s.commands_accepted), static_cast<long long>(refused),
             static_cast<long long>(r.non_finite), static_cast<long long>(r.unknown_body),
             static_cast<long long>(r.over_limit), static_cast<long long>(r.undecodable),
             static_cast<long long>(r.stale_sequence), static_cast<long long>(r.queue_full),
             static_cast<long long>(r.invalid), static_cast<long long>(r.over_share),
             static_cast<long long>(r.rate_limited), static_cast<long long>(r.not_permitted));
  for (const rigid::SourceRefusals& by : s.refused_by_source) {
    out << fmt("  refused from %s: %lld (last: %s)\n", by.sender.c_str(),
               static_cast<long long>(by.count), by.last_reason.c_str());
  }
  for (const auto& [name, c] : {std::pair{"dds", s.dds}, std::pair{"lcm", s.lcm}}) {
    out << fmt("  %s: sent %lld, send failures %lld, received %lld, undecodable %lld\n", name,
               static_cast<long long>(c.sent), static_cast<long long>(c.send_failures),
               static_cast<long long>(c.received), static_cast<long long>(c.decode_failures));
  }
  out.flush();
}

int stats(const CtlOptions& o, Session& session, const clients::DdsLog& log,
          util::SignalWatcher& signals, std::ostream& out, std::ostream& err) {
  std::mutex mutex;
  std::condition_variable changed;
  std::deque<rigid::StatsReport> reports;
  const HandlerScope handlers(session);
  session.on_each_stats([&](const rigid::StatsReport& s) {
    {
      const std::lock_guard lock(mutex);
      reports.push_back(s);
    }
    changed.notify_one();
  });
  const std::int64_t wanted = o.once ? 1 : o.count.value_or(0);
  std::int64_t printed = 0;
  auto last = std::chrono::steady_clock::now();
  // Stats come once a second; a reliable keep-last-1 DDS reader also gets the last one at once.
  const auto patience = std::max<std::chrono::milliseconds>(o.timeout, 1500ms);
  while (wanted == 0 || printed < wanted) {
    if (signals.wait(0ms)) break;
    std::unique_lock lock(mutex);
    changed.wait_for(lock, 100ms, [&] { return !reports.empty(); });
    auto got = std::exchange(reports, {});
    lock.unlock();
    const auto now = std::chrono::steady_clock::now();
    if (got.empty()) {
      if (now - last > patience) {
        err << no_answer(o, log, "Stats") << '\n';
        return kExitTimeout;
      }
      continue;
    }
    last = now;
    for (const auto& s : got) {
      if (printed > 0) out << '\n';
      print_stats(s, out);
      if (++printed >= wanted && wanted != 0) break;
    }
  }
  return kExitOk;
}

}  // namespace

int run(const CtlOptions& o, util::SignalWatcher& signals, std::ostream& out, std::ostream& err) {
  const clients::DdsLog log;  // before the bus: Cyclone's lines are told in rigidctl's words
  std::unique_ptr<Session> session;
  try {
    session = std::make_unique<Session>(o.bus);
  } catch (const client::BusError& e) {
    err << "rigidctl: " << clients::bus_error_line(e.what(), o.bus, log) << '\n';
    return kExitFailed;
  }
  switch (o.command) {
    case Command::kBodies:
      return bodies(o, *session, log, out, err);
    case Command::kEcho:
      return echo(o, *session, log, signals, out, err);
    case Command::kStats:
      return stats(o, *session, log, signals, out, err);
    case Command::kPush:
      return push(o, *session, log, out, err);
    case Command::kSet:
      return edit(o, *session, log, out, err);
    case Command::kReset:
      if (!o.body.empty()) return edit(o, *session, log, out, err);
      return control(o, *session, log, out, err);
    case Command::kPause:
    case Command::kResume:
    case Command::kStep:
    case Command::kRate:
      return control(o, *session, log, out, err);
  }
  return kExitFailed;
}

}  // namespace rigid::ctl
