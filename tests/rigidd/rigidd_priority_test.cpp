// Where rigidd's threads run in realtime mode, read from /proc while it runs: the loop at
// SCHED_FIFO 10 and each bus's publisher at 9, all pinned to one CPU; the physics pool's worker
// at normal priority on the other CPUs, or with --rt-workers at SCHED_FIFO 8 there. Each thread
// carries the name of its role (util/thread_name.hpp), which is checked against what it does.
// Whether rigidd has the privilege to take real-time priority is decided by the test itself (a
// thread of its own tries), not taken from rigidd's start line: with it, the loop must be at
// SCHED_FIFO; without it (not root), nothing may be, and rigidd must say so. Both buses open (the
// default), so this needs the network set up like the other rigidd tests.
#include <gtest/gtest.h>
#include <sched.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "rigidd_process.hpp"
#include "util/cpu_affinity.hpp"

namespace rigid::rigidd::testing {
namespace {

using namespace std::chrono_literals;

struct ThreadInfo {
  int tid = 0;
  std::string name;     // its comm (proc(5)), as top -H shows it
  int policy = 0;       // SCHED_OTHER 0, SCHED_FIFO 1
  int rt_priority = 0;  // 1 .. 99 at SCHED_FIFO
  cpu_set_t cpus{};
};

// proc(5): /proc/PID/task/TID/stat, fields 40 (rt_priority) and 41 (policy), counted after the
// command name's closing parenthesis (the name may hold spaces) as fields 3 on.
std::vector<ThreadInfo> threads_of(pid_t pid) {
  std::vector<ThreadInfo> out;
  const std::filesystem::path dir = "/proc/" + std::to_string(pid) + "/task";
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    std::ifstream in(e.path() / "stat");
    std::string stat((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::size_t close = stat.rfind(')');
    if (close == std::string::npos) continue;  // the thread ended between the listing and here
    std::istringstream fields(stat.substr(close + 2));
    std::vector<std::string> f;
    for (std::string w; fields >> w;)
      f.push_back(w);
    if (f.size() < 39) continue;
    ThreadInfo t;
    t.tid = std::stoi(e.path().filename().string());
    const std::size_t open = stat.find('(');
    t.name = stat.substr(open + 1, close - open - 1);
    t.rt_priority = std::stoi(f[40 - 3]);
    t.policy = std::stoi(f[41 - 3]);
    CPU_ZERO(&t.cpus);
    if (sched_getaffinity(t.tid, sizeof t.cpus, &t.cpus) != 0) continue;
    out.push_back(t);
  }
  return out;
}

bool wait_for_text(const RigiddProcess& p, const std::string& text,
                   std::chrono::milliseconds patience) {
  const auto deadline = std::chrono::steady_clock::now() + patience;
  while (std::chrono::steady_clock::now() < deadline) {
    if (p.stderr_text().find(text) != std::string::npos) return true;
    if (!p.running()) return false;
    std::this_thread::sleep_for(20ms);
  }
  return false;
}

// Whether rigidd may take real-time priority, decided here rather than taken from its word: a
// thread of this process does what rigidd's loop does (pinned to the last allowed CPU, then
// SCHED_FIFO 10) and goes back. rigidd, started by this process, has its credentials and limits
// (CAP_SYS_NICE, RLIMIT_RTPRIO, the cgroup's real-time budget). As root with the privilege (CI),
// the loop must then be at SCHED_FIFO.
struct Privilege {
  bool pin = false;
  bool fifo = false;
};
Privilege probe_privilege() {
  Privilege out;
  std::thread probe([&out] {
    const int cpu = util::last_allowed_cpu();
    out.pin = cpu >= 0 && util::pin_to_cpu(pthread_self(), cpu);
    sched_param p{};
    p.sched_priority = 10;
    out.fifo = pthread_setschedparam(pthread_self(), SCHED_FIFO, &p) == 0;
    if (out.fifo) {
      p.sched_priority = 0;
      (void)pthread_setschedparam(pthread_self(), SCHED_OTHER, &p);
    }
  });
  probe.join();
  return out;
}

int allowed_cpus() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) != 0) return 0;
  return CPU_COUNT(&set);
}

void check_layout(bool rt_workers) {
  SCOPED_TRACE(rt_workers ? "--rt-workers" : "default");
  std::vector<std::string> args = {
      "--scene",   std::string(RIGIDD_TEST_SCENES) + "/probe.pbtxt",
      "--threads", "2",
      "--prefix",  "prio" + std::to_string(rt_workers) + std::to_string(getpid())};
  if (rt_workers) args.push_back("--rt-workers");
  RigiddProcess daemon(args);
  // The start line on priorities comes last of all (Server::set_priorities), and may come after
  // the first state: wait for both.
  ASSERT_TRUE(wait_for_text(daemon, "rigidd: ready", 10s)) << daemon.stderr_text();
  ASSERT_TRUE(wait_for_text(daemon, "rigidd: loop thread: ", 10s)) << daemon.stderr_text();
  const std::string err = daemon.stderr_text();
  const std::vector<ThreadInfo> threads = threads_of(daemon.pid());
  ASSERT_GE(threads.size(), 5u);  // main, loop, two publishers, the worker, the buses' own
  // Every thread of rigid's own, once, by the name of its role (Cyclone and liblcm name theirs).
  std::multiset<std::string> names;
  for (const ThreadInfo& t : threads)
    names.insert(t.name);
  for (const char* role : {"rigid-loop", "rigid-pub-dds", "rigid-pub-lcm", "rigid-step-1",
                           "rigid-dds-in", "rigid-lcm-in", "rigid-house", "rigid-journal"}) {
    EXPECT_EQ(names.count(role), 1u) << role;
  }

  const Privilege privilege = probe_privilege();
  if (!privilege.pin || !privilege.fifo) {
    // Not privileged (or no CPU to pin the loop to): everything at normal priority, and said so.
    EXPECT_NE(err.find(privilege.pin ? "no real-time priority" : "cannot pin it to one CPU"),
              std::string::npos)
        << err;
    for (const ThreadInfo& t : threads)
      EXPECT_EQ(t.policy, SCHED_OTHER) << "thread " << t.tid;
    EXPECT_EQ(daemon.terminate(2000ms), 0);
    return;
  }
  // Privileged: rigidd must have taken it.
  EXPECT_EQ(err.find("no real-time priority"), std::string::npos) << err;
  EXPECT_EQ(err.find("cannot pin it to one CPU"), std::string::npos) << err;
  int loops = 0, publishers = 0, workers = 0, loop_cpu = -1;
  for (const ThreadInfo& t : threads) {
    if (t.policy != SCHED_FIFO) continue;
    if (t.rt_priority == 10) {
      ++loops;
      EXPECT_EQ(t.name, "rigid-loop");
      ASSERT_EQ(CPU_COUNT(&t.cpus), 1) << "the loop thread is pinned to one CPU";
      for (int c = 0; c < CPU_SETSIZE; ++c)
        if (CPU_ISSET(c, &t.cpus)) loop_cpu = c;
    }
  }
  ASSERT_EQ(loops, 1) << err;
  for (const ThreadInfo& t : threads) {
    if (t.policy != SCHED_FIFO || t.rt_priority == 10) continue;
    if (t.rt_priority == 9) {
      ++publishers;
      EXPECT_TRUE(t.name == "rigid-pub-dds" || t.name == "rigid-pub-lcm") << t.name;
      EXPECT_TRUE(CPU_COUNT(&t.cpus) == 1 && CPU_ISSET(loop_cpu, &t.cpus))
          << "a publisher off the loop's CPU";
    } else {
      EXPECT_EQ(t.rt_priority, 8) << "thread " << t.tid;
      EXPECT_EQ(t.name, "rigid-step-1");
      ++workers;
      // Never on the loop's CPU: there it would only run behind the loop.
      EXPECT_FALSE(CPU_ISSET(loop_cpu, &t.cpus)) << "a real-time worker on the loop's CPU";
    }
  }
  EXPECT_EQ(publishers, 2) << err;  // one per bus
  if (rt_workers && allowed_cpus() >= 2) {
    EXPECT_EQ(workers, 1) << err;
    EXPECT_NE(err.find("1 physics worker(s) at SCHED_FIFO priority 8"), std::string::npos) << err;
    EXPECT_EQ(err.find("never take more than this CPU"), std::string::npos) << err;
  } else {
    EXPECT_EQ(workers, 0) << err;
    EXPECT_NE(err.find("never take more than this CPU"), std::string::npos) << err;
    if (rt_workers) {
      EXPECT_NE(err.find("(--rt-workers: no other CPU)"), std::string::npos) << err;
    }
  }
  EXPECT_EQ(daemon.terminate(2000ms), 0) << daemon.stderr_text();
}

TEST(RigiddPriorities, LoopAndPublishersAreRealTimeOnOneCpuAndWorkersOnlyWithRtWorkers) {
  check_layout(false);
  check_layout(true);
}

TEST(RigiddPriorities, CheckSaysWhenTheWorkersAreRealTime) {
  const std::string scene = std::string(RIGIDD_TEST_SCENES) + "/probe.pbtxt";
  Completed r = run_to_exit({"--check", "--rt-workers", "--scene", scene});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("step workers at real-time priority (--rt-workers)"), std::string::npos)
      << r.out;
  r = run_to_exit({"--check", "--scene", scene});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.find("real-time priority"), std::string::npos) << r.out;
  // A flag: it takes no value.
  r = run_to_exit({"--rt-workers=on", "--check", "--scene", scene});
  EXPECT_EQ(r.exit_code, 2) << r.out;
  EXPECT_NE(r.err.find("unknown option '--rt-workers'"), std::string::npos) << r.err;
  // Real-time priority is for realtime mode only: elsewhere it would silently do nothing.
  r = run_to_exit({"--rt-workers", "--mode", "fast", "--check", "--scene", scene});
  EXPECT_EQ(r.exit_code, 2) << r.out;
  EXPECT_NE(r.err.find("rigidd: --rt-workers applies to --mode realtime, not 'fast'"),
            std::string::npos)
      << r.err;
}

}  // namespace
}  // namespace rigid::rigidd::testing
