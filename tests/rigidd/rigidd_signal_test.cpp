// rigidd under a service manager: systemd's notify protocol (READY=1 after the first state,
// WATCHDOG=1 while the loop runs, STOPPING=1 on the way out), read from a NOTIFY_SOCKET this test
// binds, and SIGTERM/SIGINT ending it within one second with exit status 0. Both buses open (the
// default), so this needs the network set up like the other rigidd tests.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

#include "rigidd_process.hpp"

namespace rigid::rigidd::testing {
namespace {

using namespace std::chrono_literals;

// A datagram socket standing in for systemd's notification socket.
class NotifySocket {
 public:
  NotifySocket() {
    path_ = (std::filesystem::temp_directory_path() /
             ("rigidd_notify_" + std::to_string(::getpid()) + "_" + std::to_string(counter_++)))
                .string();
    std::filesystem::remove(path_);
    fd_ = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    path_.copy(addr.sun_path, sizeof addr.sun_path - 1);
    bound_ = ::bind(fd_, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) == 0;
  }
  ~NotifySocket() {
    ::close(fd_);
    std::filesystem::remove(path_);
  }
  bool bound() const { return bound_; }
  const std::string& path() const { return path_; }

  // Waits (at most `patience`) for a message containing `text`; all messages are kept.
  bool wait_for(const std::string& text, std::chrono::milliseconds patience) {
    const auto deadline = std::chrono::steady_clock::now() + patience;
    for (;;) {
      for (const std::string& m : messages_)
        if (m.find(text) != std::string::npos) return true;
      const auto left = std::chrono::duration_cast<std::chrono::microseconds>(
          deadline - std::chrono::steady_clock::now());
      if (left.count() <= 0) return false;
      timeval tv{static_cast<time_t>(left.count() / 1'000'000),
                 static_cast<suseconds_t>(left.count() % 1'000'000)};
      ::setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
      char buffer[512];
      const ssize_t n = ::recv(fd_, buffer, sizeof buffer, 0);
      if (n > 0) messages_.emplace_back(buffer, static_cast<std::size_t>(n));
    }
  }
  const std::vector<std::string>& messages() const { return messages_; }

 private:
  static inline int counter_ = 0;
  std::string path_;
  int fd_ = -1;
  bool bound_ = false;
  std::vector<std::string> messages_;
};

std::vector<std::string> daemon_args(const std::string& tag) {
  return {"--scene", std::string(RIGIDD_TEST_SCENES) + "/probe.pbtxt", "--prefix",
          tag + std::to_string(::getpid())};
}

TEST(RigiddSignals, SigtermStopsWithin1sWithExit0AndSystemdIsNotified) {
  NotifySocket notify;
  ASSERT_TRUE(notify.bound());
  RigiddProcess daemon(daemon_args("sigterm"),
                       {"NOTIFY_SOCKET=" + notify.path(), "WATCHDOG_USEC=200000"});
  ASSERT_TRUE(notify.wait_for("READY=1", 10s)) << daemon.stderr_text();
  ASSERT_TRUE(notify.wait_for("WATCHDOG=1", 2s)) << daemon.stderr_text();
  EXPECT_EQ(daemon.terminate(1000ms), 0) << daemon.stderr_text();
  EXPECT_LE(daemon.last_stop_time(), 1000ms);
  EXPECT_TRUE(notify.wait_for("STOPPING=1", 100ms));
  const std::string err = daemon.stderr_text();
  EXPECT_NE(err.find("rigidd: ready: first state published"), std::string::npos) << err;
  EXPECT_NE(err.find("rigidd: SIGTERM: stopping"), std::string::npos) << err;
  // One short closing line (the full summary and histogram only with --verbose).
  EXPECT_NE(err.find("rigidd: stopped after "), std::string::npos) << err;
  EXPECT_EQ(err.find("lateness_histogram_ns"), std::string::npos) << err;
  // READY=1 came before any STOPPING=1.
  std::size_t ready = 0, stopping = 0;
  for (std::size_t i = 0; i < notify.messages().size(); ++i) {
    if (notify.messages()[i].find("READY=1") != std::string::npos && ready == 0) ready = i + 1;
    if (notify.messages()[i].find("STOPPING=1") != std::string::npos) stopping = i + 1;
  }
  EXPECT_LT(ready, stopping);
}

TEST(RigiddSignals, SigintStopsWithin1sWithExit0EvenInLockstep) {
  std::vector<std::string> args = daemon_args("sigint");
  args.insert(args.end(), {"--mode", "lockstep"});
  NotifySocket notify;
  RigiddProcess daemon(args, {"NOTIFY_SOCKET=" + notify.path()});
  ASSERT_TRUE(notify.wait_for("READY=1", 10s)) << daemon.stderr_text();
  const auto t0 = std::chrono::steady_clock::now();
  daemon.signal(SIGINT);
  const auto status = daemon.wait_exit(1000ms);
  ASSERT_TRUE(status) << "still running 1 s after SIGINT";
  EXPECT_LE(std::chrono::steady_clock::now() - t0, 1000ms);
  EXPECT_TRUE(WIFEXITED(*status) && WEXITSTATUS(*status) == 0) << daemon.stderr_text();
}

}  // namespace
}  // namespace rigid::rigidd::testing
