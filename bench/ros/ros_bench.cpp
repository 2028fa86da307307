// What rigidd --ros costs, measured from outside against a running rigidd (bench/ros/ros_bench.sh
// runs it side by side with and without --ros):
//
//   ros_bench --pid PID [--duration 20] [--push-every-ms 20] [--ros]
//
// A client of rigid's own topics: reads rigid/state (best-effort, as rigid's clients do) and every
// push-every-ms pushes body 0 with a one-tick rigid wrench (rigid/wrench, ttl 0), alternating its
// sign; half a period later it sets body 1's held force, alternating between a force and none,
// through rigid's topic (a wrench held 60 s, replaced by the next). With --ros it sets body 1's
// force through ROS instead (a geometry_msgs/WrenchStamped on rt/rigid/b1/wrench: a ROS wrench
// holds until replaced) and also reads /tf (reliable, tf2's QoS): both runs send the same
// commands and rigidd publishes the same states.
//
// Reports for the run (after a warm-up in which each kind of push has come back once):
//   RESULT wrench_to_state_us rigid p50 P p99 P n N held|ros p50 P p99 P n N
//     from the publish call to the arrival of the first rigid/state in which the pushed body's
//     velocity shows it (for the ROS wrench: the first state after its publication whose velocity
//     change differs from the previous state's);
//   RESULT process_cpu_percent X     rigidd's CPU over the run, % of one CPU;
//   RESULT thread_cpu_percent NAME X ...   by thread name (rigid-pub-dds: the DDS publisher,
//     which sends rigid/state and, with --ros, /tf and /clock);
//   RESULT states N tf N             received over the run.
#include <dds/dds.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "rigid.h"     // idlc's C types of msgs/rigid.idl
#include "ros_msgs.h"  // ROS 2's WrenchStamped and TFMessage (tests/ros/secure/ros_msgs.idl)

namespace {

namespace fs = std::filesystem;

std::int64_t now_ns() {
  timespec t{};
  clock_gettime(CLOCK_MONOTONIC, &t);
  return static_cast<std::int64_t>(t.tv_sec) * 1'000'000'000 + t.tv_nsec;
}

// CPU time (user + system, clock ticks) of process pid, and of its threads by name.
long process_ticks(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string stat((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t close = stat.rfind(')');
  if (close == std::string::npos) return 0;
  std::istringstream fields(stat.substr(close + 1));
  std::string f;
  long ticks = 0;
  for (int k = 3; k <= 15 && fields >> f; ++k)
    if (k == 14 || k == 15) ticks += std::atol(f.c_str());
  return ticks;
}

std::map<std::string, long> thread_ticks(pid_t pid) {
  std::map<std::string, long> use;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator("/proc/" + std::to_string(pid) + "/task", ec)) {
    std::ifstream in(e.path() / "stat");
    std::string stat((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::size_t open = stat.find('('), close = stat.rfind(')');
    if (open == std::string::npos || close == std::string::npos || close < open) continue;
    std::istringstream fields(stat.substr(close + 1));
    std::string f;
    long& t = use[stat.substr(open + 1, close - open - 1)];
    for (int k = 3; k <= 15 && fields >> f; ++k)
      if (k == 14 || k == 15) t += std::atol(f.c_str());
  }
  return use;
}

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(p * static_cast<double>(v.size() - 1) + 0.5)];
}

// A push waiting for the state that shows it.
struct Pending {
  std::atomic<std::int64_t> sent_ns{0};  // 0: none pending
  bool measure = false;
};

}  // namespace

int main(int argc, char** argv) {
  pid_t pid = 0;
  double duration = 20.0;
  int push_every_ms = 20;
  bool ros = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const auto value = [&]() -> std::string { return i + 1 < argc ? argv[++i] : ""; };
    if (a == "--pid") {
      pid = std::atoi(value().c_str());
    } else if (a == "--duration") {
      duration = std::atof(value().c_str());
    } else if (a == "--push-every-ms") {
      push_every_ms = std::atoi(value().c_str());
    } else if (a == "--ros") {
      ros = true;
    } else {
      std::fprintf(stderr,
                   "usage: ros_bench --pid PID [--duration S] [--push-every-ms MS] [--ros]\n");
      return 2;
    }
  }
  if (pid <= 0 || duration <= 0 || push_every_ms < 2) {
    std::fprintf(stderr, "ros_bench: --pid is required; --duration > 0; --push-every-ms >= 2\n");
    return 2;
  }

  const dds_entity_t participant = dds_create_participant(0, nullptr, nullptr);
  if (participant < 0) return 1;
  dds_qos_t* be = dds_create_qos();
  dds_qset_reliability(be, DDS_RELIABILITY_BEST_EFFORT, 0);
  dds_qset_history(be, DDS_HISTORY_KEEP_LAST, 256);
  dds_qos_t* rel = dds_create_qos();
  dds_qset_reliability(rel, DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
  dds_qset_history(rel, DDS_HISTORY_KEEP_LAST, 100);
  const dds_entity_t state_topic =
      dds_create_topic(participant, &rigid_WorldState_desc, "rigid/state", nullptr, nullptr);
  const dds_entity_t states = dds_create_reader(participant, state_topic, be, nullptr);
  const dds_entity_t wrench_topic =
      dds_create_topic(participant, &rigid_Wrench_desc, "rigid/wrench", nullptr, nullptr);
  dds_qos_t* wq = dds_create_qos();
  dds_qset_reliability(wq, DDS_RELIABILITY_RELIABLE, DDS_MSECS(10));
  dds_qset_history(wq, DDS_HISTORY_KEEP_LAST, 256);
  const dds_entity_t rigid_writer = dds_create_writer(participant, wrench_topic, wq, nullptr);
  dds_entity_t tf = 0, ros_writer = 0;
  if (ros) {
    const dds_entity_t tf_topic = dds_create_topic(participant, &tf2_msgs_msg_dds__TFMessage__desc,
                                                   "rt/tf", nullptr, nullptr);
    tf = dds_create_reader(participant, tf_topic, rel, nullptr);
    const dds_entity_t ros_topic =
        dds_create_topic(participant, &geometry_msgs_msg_dds__WrenchStamped__desc,
                         "rt/rigid/b1/wrench", nullptr, nullptr);
    dds_qos_t* rq = dds_create_qos();
    dds_qset_reliability(rq, DDS_RELIABILITY_RELIABLE, DDS_MSECS(10));
    dds_qset_history(rq, DDS_HISTORY_KEEP_LAST, 10);
    ros_writer = dds_create_writer(participant, ros_topic, rq, nullptr);
    dds_delete_qos(rq);
  }
  if (states < 0 || rigid_writer < 0 || tf < 0 || ros_writer < 0) {
    std::fprintf(stderr, "ros_bench: cannot create the readers and writers\n");
    return 1;
  }

  Pending rigid_push, ros_push;
  std::mutex lat_mutex;
  std::vector<double> rigid_us, ros_us;
  std::atomic<bool> stop{false};
  std::atomic<long> n_states{0}, n_tf{0};
  std::atomic<bool> measuring{false};
  // The states: a pushed body's velocity (x) against its previous state's shows the push; for
  // body 1 (a held force) its velocity's change per tick between states does (states are not
  // evenly spaced: a tick with a new command publishes one).
  std::thread reader([&] {
    double v0 = NAN, v1 = NAN, dv1 = 0.0;
    std::int64_t tick1 = 0;
    while (!stop.load()) {
      void* samples[16] = {};
      dds_sample_info_t infos[16];
      const dds_return_t n = dds_take(states, samples, infos, 16, 16);
      const std::int64_t t = now_ns();
      for (dds_return_t k = 0; k < n; ++k) {
        if (!infos[k].valid_data) continue;
        const auto* s = static_cast<const rigid_WorldState*>(samples[k]);
        if (s->linear_velocity._length < 6) continue;
        ++n_states;
        const double a = s->linear_velocity._buffer[0];
        const double b = s->linear_velocity._buffer[3];
        const std::int64_t ticks = s->tick - tick1;
        const double dv =
            std::isnan(v1) || ticks <= 0 ? dv1 : (b - v1) / static_cast<double>(ticks);
        if (!std::isnan(v0) && a != v0) {
          const std::int64_t sent = rigid_push.sent_ns.exchange(0);
          if (sent != 0 && measuring.load()) {
            const std::lock_guard lock(lat_mutex);
            rigid_us.push_back(static_cast<double>(t - sent) * 1e-3);
          }
        }
        if (!std::isnan(v1) && std::abs(dv - dv1) > 1e-9) {
          const std::int64_t sent = ros_push.sent_ns.exchange(0);
          if (sent != 0 && measuring.load()) {
            const std::lock_guard lock(lat_mutex);
            ros_us.push_back(static_cast<double>(t - sent) * 1e-3);
          }
        }
        v0 = a;
        v1 = b;
        dv1 = dv;
        tick1 = s->tick;
      }
      if (n > 0) dds_return_loan(states, samples, n);
      if (ros) {
        void* ts[8] = {};
        dds_sample_info_t ti[8];
        const dds_return_t m = dds_take(tf, ts, ti, 8, 8);
        if (m > 0) {
          n_tf += m;
          dds_return_loan(tf, ts, m);
        }
      }
      if (n <= 0) std::this_thread::sleep_for(std::chrono::microseconds(100));
    }
  });

  // Wait for the bus, then warm up: each kind of push comes back once before the run.
  std::this_thread::sleep_for(std::chrono::seconds(2));
  std::int64_t seq = 0;
  int sign = 1;
  bool force_on = false;
  const auto push = [&] {
    rigid_Wrench w{};
    w.source = 77;
    w.seq = ++seq;
    w.body_id = 0;
    w.force[0] = sign;
    sign = -sign;
    rigid_push.sent_ns.store(now_ns());
    dds_write(rigid_writer, &w);
  };
  // Body 1's held force: through ROS with --ros; without, the same commands through rigid's
  // topic (a wrench held for 60 s, replaced by the next), so that both runs send as many
  // commands and rigidd publishes as many states (each tick with a new command publishes one).
  const auto push_ros = [&] {
    force_on = !force_on;
    ros_push.sent_ns.store(now_ns());
    if (ros) {
      geometry_msgs_msg_dds__WrenchStamped_ m{};
      m.header.frame_id = const_cast<char*>("world");
      m.wrench.force.x = force_on ? 1.0 : 0.0;
      dds_write(ros_writer, &m);
    } else {
      rigid_Wrench w{};
      w.source = 78;
      w.seq = ++seq;
      w.body_id = 1;
      w.force[0] = force_on ? 1.0 : 0.0;
      w.ttl = 60.0;
      dds_write(rigid_writer, &w);
    }
  };
  const std::int64_t period = static_cast<std::int64_t>(push_every_ms) * 1'000'000;
  const auto one_period = [&] {
    push();
    std::this_thread::sleep_for(std::chrono::nanoseconds(period / 2));
    push_ros();
    std::this_thread::sleep_for(std::chrono::nanoseconds(period / 2));
  };
  for (int i = 0; i < 50; ++i)
    one_period();
  const long cpu0 = process_ticks(pid);
  const auto threads0 = thread_ticks(pid);
  const long states0 = n_states.load(), tf0 = n_tf.load();
  const std::int64_t t0 = now_ns();
  measuring.store(true);
  while (now_ns() - t0 < static_cast<std::int64_t>(duration * 1e9))
    one_period();
  measuring.store(false);
  const double seconds = static_cast<double>(now_ns() - t0) * 1e-9;
  const long cpu1 = process_ticks(pid);
  const auto threads1 = thread_ticks(pid);
  stop.store(true);
  reader.join();

  const double per_tick = 100.0 / (static_cast<double>(::sysconf(_SC_CLK_TCK)) * seconds);
  {
    const std::lock_guard lock(lat_mutex);
    std::printf("RESULT wrench_to_state_us rigid p50 %.1f p99 %.1f n %zu",
                percentile(rigid_us, 0.5), percentile(rigid_us, 0.99), rigid_us.size());
    std::printf(" %s p50 %.1f p99 %.1f n %zu", ros ? "ros" : "held", percentile(ros_us, 0.5),
                percentile(ros_us, 0.99), ros_us.size());
    std::printf("\n");
  }
  std::printf("RESULT process_cpu_percent %.1f\n", static_cast<double>(cpu1 - cpu0) * per_tick);
  std::printf("RESULT thread_cpu_percent");
  for (const auto& [name, t] : threads1) {
    const auto b = threads0.find(name);
    const double p = static_cast<double>(t - (b == threads0.end() ? 0 : b->second)) * per_tick;
    if (p >= 0.1) std::printf(" %s %.1f", name.c_str(), p);
  }
  std::printf(" (%% of one CPU over %.1f s)\n", seconds);
  std::printf("RESULT states %ld tf %ld\n", n_states.load() - states0, n_tf.load() - tf0);
  dds_delete_qos(be);
  dds_delete_qos(rel);
  dds_delete_qos(wq);
  dds_delete(participant);
  return 0;
}
