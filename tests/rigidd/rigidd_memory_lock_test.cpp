// rigidd locks its memory in realtime mode (rigidd/memory_lock.hpp) and says so, or says why it
// could not and runs on; in other modes it leaves its memory alone. Read from its log and from
// /proc/PID/status (VmLck: the size of its locked mappings) while it runs. Both buses open (the
// default), so this needs the network set up like the other rigidd tests.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "rigidd_process.hpp"

namespace rigid::rigidd::testing {
namespace {

using namespace std::chrono_literals;

// VmLck of /proc/PID/status in kB; -1 if there is none.
long locked_kib(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("VmLck:", 0) == 0) return std::stol(line.substr(6));
  return -1;
}

// Whether this process may lock any amount of memory: CAP_IPC_LOCK (bit 14) in its effective set.
bool may_lock_memory() {
  std::ifstream in("/proc/self/status");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("CapEff:", 0) == 0) return (std::stoull(line.substr(7), nullptr, 16) >> 14) & 1;
  return false;
}

// The sanitizers' runtimes make mlockall a no-op that reports success; rigidd, built with the
// same flags as this test, then says it locked nothing.
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
constexpr bool kSanitized = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
constexpr bool kSanitized = true;
#else
constexpr bool kSanitized = false;
#endif
#else
constexpr bool kSanitized = false;
#endif
constexpr const char* kLockedNothing =
    "rigidd: memory: not locked (mlockall returned without locking anything, as it does in a "
    "sanitizer build)";

bool wait_for_text(const RigiddProcess& p, const std::string& text) {
  const auto deadline = std::chrono::steady_clock::now() + 10s;
  while (std::chrono::steady_clock::now() < deadline) {
    if (p.stderr_text().find(text) != std::string::npos) return true;
    if (!p.running()) return false;
    std::this_thread::sleep_for(20ms);
  }
  return false;
}

std::vector<std::string> args_for(const std::string& tag) {
  return {"--scene", std::string(RIGIDD_TEST_SCENES) + "/probe.pbtxt", "--prefix",
          "mlock" + tag + std::to_string(getpid())};
}

TEST(RigiddMemoryLock, RealtimeModeLocksItsMemoryWhenAllowed) {
  RigiddProcess daemon(args_for("rt"));
  ASSERT_TRUE(wait_for_text(daemon, "rigidd: ready")) << daemon.stderr_text();
  const std::string err = daemon.stderr_text();
  const long locked = locked_kib(daemon.pid());
  if (kSanitized) {
    EXPECT_NE(err.find(kLockedNothing), std::string::npos) << err;
    EXPECT_EQ(locked, 0) << err;
  } else if (may_lock_memory()) {
    EXPECT_NE(err.find("rigidd: memory: locked in RAM"), std::string::npos) << err;
    EXPECT_GT(locked, 0) << err;
  } else {
    // Without the capability it depends on RLIMIT_MEMLOCK; either way it is said.
    EXPECT_TRUE(err.find("rigidd: memory: locked in RAM") != std::string::npos ||
                err.find("rigidd: memory: not locked (mlockall: ") != std::string::npos)
        << err;
  }
  EXPECT_EQ(daemon.terminate(2000ms), 0) << daemon.stderr_text();
}

TEST(RigiddMemoryLock, WithoutThePrivilegeItSaysWhyAndRunsOn) {
  // A 64 KiB limit (rigidd maps far more) and, as root, no CAP_IPC_LOCK (which would bypass it).
  std::vector<std::string> args{"--memlock=65536:65536"};
  if (geteuid() == 0) {
    for (const char* a : {"/usr/bin/setpriv", "--bounding-set=-ipc_lock", "--inh-caps=-ipc_lock"})
      args.push_back(a);
  }
  args.push_back(RIGIDD_EXE);
  for (const std::string& a : args_for("no"))
    args.push_back(a);
  RigiddProcess daemon("/usr/bin/prlimit", args, {});
  ASSERT_TRUE(wait_for_text(daemon, "rigidd: ready")) << daemon.stderr_text();
  const std::string err = daemon.stderr_text();
  if (kSanitized) {
    EXPECT_NE(err.find(kLockedNothing), std::string::npos) << err;
  } else {
    EXPECT_NE(err.find("rigidd: memory: not locked (mlockall: Cannot allocate memory; "
                       "RLIMIT_MEMLOCK 64 KiB): "),
              std::string::npos)
        << err;
    EXPECT_NE(err.find("give rigidd CAP_IPC_LOCK or LimitMEMLOCK=infinity"), std::string::npos)
        << err;
  }
  EXPECT_EQ(locked_kib(daemon.pid()), 0) << err;
  EXPECT_EQ(daemon.terminate(2000ms), 0) << daemon.stderr_text();
}

TEST(RigiddMemoryLock, OtherModesLeaveMemoryAlone) {
  std::vector<std::string> args = args_for("fast");
  args.insert(args.end(), {"--mode", "fast"});
  RigiddProcess daemon(args);
  ASSERT_TRUE(wait_for_text(daemon, "rigidd: ready")) << daemon.stderr_text();
  const std::string err = daemon.stderr_text();
  EXPECT_EQ(err.find("rigidd: memory:"), std::string::npos) << err;
  EXPECT_EQ(locked_kib(daemon.pid()), 0) << err;
  EXPECT_EQ(daemon.terminate(2000ms), 0) << daemon.stderr_text();
}

}  // namespace
}  // namespace rigid::rigidd::testing
