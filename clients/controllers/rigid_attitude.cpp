// rigid-attitude: an example controller. Reads the body's state from rigidd, runs the attitude law
// of attitude_control.hpp at a fixed rate, and publishes the six thrusters' forces as wrenches.
#include <signal.h>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <numbers>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "attitude_control.hpp"
#include "attitude_options.hpp"
#include "cli/dds_log.hpp"
#include "rigid/client/names.hpp"
#include "rigid/client/session.hpp"
#include "util/signal_watcher.hpp"

namespace {

using namespace rigid;
using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;
using controllers::Quat;
using controllers::Vec3;

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr auto kSettleHold = 1s;
constexpr auto kPrintPeriod = 200ms;

double seconds(Clock::duration d) {
  return std::chrono::duration<double>(d).count();
}

// The body to hold as one SceneInfo describes it: its id, its place in the state, and the law
// built from its inertia and shape. A restarted rigidd may run another scene: then it is resolved
// again from the new SceneInfo (the same body may have another id, or be gone).
struct Target {
  std::int32_t id = 0;
  std::size_t index = 0;  // in the state's per-body arrays
  std::string name;
  std::vector<std::int32_t> ids;  // the scene's: a state of this scene carries the same
  controllers::AttitudeController law;
};

// The target in `scene`, or nothing with the reason in `error` (one line).
std::optional<Target> resolve(const rigid::SceneDescription& scene,
                              const controllers::AttitudeOptions& o, std::string& error) {
  std::optional<std::int32_t> id;
  if (o.body.empty()) {
    if (scene.body_count() != 1) {
      error = "the scene has " + std::to_string(scene.body_count()) + " bodies: name one (" +
              client::body_list(scene) + ")";
      return std::nullopt;
    }
    id = scene.ids[0];
  } else {
    id = client::find_body(scene, o.body);
  }
  if (!id) {
    error = "no body " + clients::quoted(o.body) +
            " in the scene (bodies: " + client::body_list(scene) + ")";
    return std::nullopt;
  }
  std::size_t index = 0;
  while (scene.ids[index] != *id)
    ++index;
  const std::string name = scene.names[index];
  const controllers::Mat3 I_B = controllers::inertia_from(&scene.inertia[6 * index]);
  if (I_B.trace() <= 0) {
    error = name + " is a point mass: it has no attitude to hold";
    return std::nullopt;
  }
  Vec3 half;
  if (scene.shape_kinds[index] == rigid::ShapeKind::kBox) {
    half = 0.5 * Vec3(scene.shape_dims[3 * index], scene.shape_dims[3 * index + 1],
                      scene.shape_dims[3 * index + 2]);
  } else if (o.arm) {
    half = Vec3::Constant(*o.arm);
  } else {
    error = name + " is not a box: give the thrusters' lever arm with --arm M";
    return std::nullopt;
  }
  const Quat target = controllers::from_rpy(o.target_rpy_deg[0] * kDeg, o.target_rpy_deg[1] * kDeg,
                                            o.target_rpy_deg[2] * kDeg);
  return Target{*id, index, name, scene.ids,
                controllers::AttitudeController(
                    I_B, controllers::ThrusterSet::box(half, o.max_thrust), target)};
}

void print_holding(const controllers::AttitudeOptions& o, const Target& t) {
  std::printf(
      "rigid-attitude: holding %s at roll %g pitch %g yaw %g deg with 6 thrusters of %g N "
      "at %g Hz\n",
      t.name.c_str(), o.target_rpy_deg[0], o.target_rpy_deg[1], o.target_rpy_deg[2], o.max_thrust,
      o.rate_hz);
  std::fflush(stdout);
}

int run(const controllers::AttitudeOptions& o, util::SignalWatcher& signals) {
  const clients::DdsLog dds_log;  // before the bus: Cyclone's lines are told in our words
  std::optional<client::Session> joined;
  try {
    joined.emplace(o.bus);
  } catch (const client::BusError& e) {
    std::cerr << "rigid-attitude: " << clients::bus_error_line(e.what(), o.bus, dds_log) << '\n';
    return clients::kExitFailed;
  }
  client::Session& session = *joined;
  const auto scene = session.wait_scene(o.timeout);
  // After the wait: the scene it brought is the one resolved below, not a change to act on (taken
  // before, it made the loop resolve the same scene again and print its start line twice).
  std::uint64_t generation = session.scene_generation();
  if (!scene) {
    std::cerr << "rigid-attitude: no SceneInfo from rigidd within "
              << static_cast<double>(o.timeout.count()) / 1000.0 << " s on "
              << client::describe(o.bus) << clients::no_rigidd_hint(o.bus, dds_log) << '\n';
    return clients::kExitTimeout;
  }
  std::string error;
  std::optional<Target> target = resolve(*scene, o, error);
  if (!target) {
    std::cerr << "rigid-attitude: " << error << '\n';
    return clients::kExitUsage;
  }
  print_holding(o, *target);

  const auto period = std::chrono::duration_cast<Clock::duration>(1s / o.rate_hz);
  // A wrench outlives a few periods: if this controller stops, its thrust stops with it.
  const double ttl = 3.0 * seconds(period);

  rigid::WrenchCommand w;
  w.force_frame = rigid::Frame::kBody;
  w.ttl = ttl;
  const auto publish = [&](const controllers::Thrusts& u, double wrench_ttl) {
    const auto& thrusters = target->law.thrusters().thrusters();
    w.body_id = target->id;
    w.body_name = target->name;  // DDS Security sends it through that body's partition
    for (std::size_t i = 0; i < thrusters.size(); ++i) {
      const Vec3 f = u[i] * thrusters[i].axis_B;
      w.key = static_cast<std::int32_t>(i);
      w.force = {f.x(), f.y(), f.z()};
      w.point = {thrusters[i].point_B.x(), thrusters[i].point_B.y(), thrusters[i].point_B.z()};
      w.ttl = wrench_ttl;
      session.send(w);
    }
  };

  const auto start = Clock::now();
  auto next = start;
  auto next_print = start;
  bool within = false;  // of the target since within_since
  Clock::time_point within_since = start;
  bool settled = false;
  std::int64_t last_tick = -1;
  auto last_new_state = start;
  int status = clients::kExitOk;
  // Refusals: each is told at once (rigidd answers a few a second at most); thrust that stays
  // refused for kRefusedFor ends the run with a failure, so that nobody mistakes printed thrust
  // for thrust that acts.
  constexpr auto kRefusedFor = 2s;
  std::optional<Clock::time_point> refused_since;
  Clock::time_point last_refusal = start;
  for (;;) {
    const auto now = Clock::now();
    if (const auto refusal = session.take_refusal()) {
      std::fprintf(stderr, "rigid-attitude: rigidd refused a thrust command: %s\n",
                   refusal->message.c_str());
      if (!refused_since) refused_since = now;
      last_refusal = now;
    } else if (refused_since && now - last_refusal > 1s) {
      refused_since.reset();  // accepted again
    }
    if (refused_since && now - *refused_since >= kRefusedFor) {
      std::fprintf(stderr,
                   "rigid-attitude: its commands have been refused for %.0f s: stopping (%lld "
                   "refusals answered)\n",
                   seconds(now - *refused_since),
                   static_cast<long long>(session.wrenches_refused()));
      return clients::kExitFailed;
    }
    if (o.duration && seconds(now - start) >= *o.duration) {
      if (o.exit_when_settled && !settled) {
        std::printf("rigid-attitude: not settled within %g deg after %g s\n", o.settle_deg,
                    *o.duration);
        status = clients::kExitFailed;
      }
      break;
    }
    if (session.scene_generation() != generation) {
      // A restarted rigidd with another scene: find the body in it again.
      generation = session.scene_generation();
      std::optional<Target> now_target = resolve(*session.wait_scene(0ms), o, error);
      if (!now_target) {
        std::cerr << "rigid-attitude: rigidd's scene changed: " << error << '\n';
        return clients::kExitFailed;
      }
      target = std::move(now_target);
      print_holding(o, *target);
    }
    const auto state = session.latest_state();
    if (state && state->tick != last_tick) {
      last_tick = state->tick;
      last_new_state = now;
    }
    if (now - last_new_state > o.timeout) {
      std::cerr << "rigid-attitude: no state from rigidd for "
                << static_cast<double>(o.timeout.count()) / 1000.0 << " s on "
                << client::describe(o.bus) << '\n';
      return clients::kExitTimeout;
    }
    // Only a state of the target's scene (a new rigidd's may come before its SceneInfo).
    if (state && state->ids == target->ids) {
      const double* q = &state->orientation[4 * target->index];
      const double* wv = &state->angular_velocity[3 * target->index];
      const Quat q_WB(q[0], q[1], q[2], q[3]);
      const Vec3 w_W(wv[0], wv[1], wv[2]);
      const controllers::Thrusts u = target->law.thrusts(q_WB, w_W);
      publish(u, ttl);
      const double error_deg = controllers::angle_between(q_WB, target->law.target()) / kDeg;
      if (error_deg >= o.settle_deg) {
        within = false;
      } else if (!within) {
        within = true;
        within_since = now;
      }
      if (now >= next_print) {
        double thrust = 0;
        for (const double ui : u)
          thrust = std::max(thrust, std::abs(ui));
        std::printf("t %7.2f s  error %8.3f deg  rate %6.3f rad/s  thrust max %5.2f N\n",
                    seconds(now - start), error_deg, w_W.norm(), thrust);
        std::fflush(stdout);
        next_print = now + kPrintPeriod;
      }
      if (!settled && within && now - within_since >= kSettleHold) {
        settled = true;
        std::printf("rigid-attitude: settled within %g deg after %.2f s\n", o.settle_deg,
                    seconds(within_since - start));
        std::fflush(stdout);
        if (o.exit_when_settled) break;
      }
    }
    next += period;
    if (next < Clock::now()) next = Clock::now();  // fell behind: do not try to catch up
    if (signals.wait(std::chrono::duration_cast<std::chrono::milliseconds>(next - Clock::now()))) {
      break;
    }
  }
  publish({}, 0.0);  // thrust off now, not a ttl later
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string_view> args(argv + 1, argv + argc);
  controllers::AttitudeOptions options;
  try {
    options = controllers::parse_options(args);
  } catch (const clients::UsageError& e) {
    std::cerr << "rigid-attitude: " << e.what() << '\n';
    return clients::kExitUsage;
  }
  if (options.help) {
    std::cout << controllers::usage();
    return clients::kExitOk;
  }
  try {
    util::SignalWatcher signals({SIGINT, SIGTERM});  // before the bus starts its threads
    return run(options, signals);
  } catch (const std::exception& e) {
    std::cerr << "rigid-attitude: " << e.what() << '\n';
    return clients::kExitFailed;
  }
}
