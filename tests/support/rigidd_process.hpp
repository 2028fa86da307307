// rigidd as a child process for tests: started in its own process group with stdout and stderr in
// files, stopped by PID with a signal, and killed with its whole group (SIGKILL) if a test ends
// while it still runs, so a failing test never leaves a daemon behind. Other programs a test runs
// beside it (client tools, lcm-logger) are started and stopped the same way.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace rigid::rigidd::testing {

class RigiddProcess {
 public:
  // Starts RIGIDD_EXE with `args`; `extra_env` ("NAME=value") is added to this process's
  // environment (which carries CYCLONEDDS_URI from ctest), replacing a variable of that name.
  explicit RigiddProcess(const std::vector<std::string>& args,
                         const std::vector<std::string>& extra_env = {});
  // Starts `program` (a path) instead of rigidd.
  RigiddProcess(const std::string& program, const std::vector<std::string>& args,
                const std::vector<std::string>& extra_env);
  ~RigiddProcess();
  RigiddProcess(const RigiddProcess&) = delete;
  RigiddProcess& operator=(const RigiddProcess&) = delete;

  pid_t pid() const { return pid_; }
  bool running() const { return !status_; }
  void signal(int sig) const;
  // The wait(2) status once it has exited within `patience`, else nothing.
  std::optional<int> wait_exit(std::chrono::milliseconds patience);
  // SIGTERM, then the exit code if it exited normally within `patience` (-1 otherwise; a
  // daemon still running is then killed).
  int terminate(std::chrono::milliseconds patience = std::chrono::milliseconds(1000));
  // How long the last terminate() took from the signal to the exit.
  std::chrono::milliseconds last_stop_time() const { return stop_time_; }

  std::string stderr_text() const;
  std::string stdout_text() const;

 private:
  std::filesystem::path dir_;
  pid_t pid_ = -1;
  std::optional<int> status_;
  std::chrono::milliseconds stop_time_{0};
};

// Runs rigidd to completion (for the cases that exit at once: bad input, --check, --help).
struct Completed {
  int exit_code = -1;  // -1: killed or timed out
  std::string out, err;
};
Completed run_to_exit(const std::vector<std::string>& args,
                      std::chrono::milliseconds patience = std::chrono::milliseconds(10000));
// The same for another program (a path).
Completed run_program_to_exit(
    const std::string& program, const std::vector<std::string>& args,
    std::chrono::milliseconds patience = std::chrono::milliseconds(10000));

int count_lines(const std::string& text);

}  // namespace rigid::rigidd::testing
