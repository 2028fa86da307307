#include "rigidd_process.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <thread>

extern char** environ;

namespace rigid::rigidd::testing {
namespace {

std::filesystem::path fresh_dir() {
  static std::atomic<int> counter{0};
  const auto dir = std::filesystem::temp_directory_path() /
                   ("rigidd_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

std::string read(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

RigiddProcess::RigiddProcess(const std::vector<std::string>& args,
                             const std::vector<std::string>& extra_env)
    : RigiddProcess(RIGIDD_EXE, args, extra_env) {}

RigiddProcess::RigiddProcess(const std::string& program, const std::vector<std::string>& args,
                             const std::vector<std::string>& extra_env)
    : dir_(fresh_dir()) {
  std::vector<std::string> argv_text{program};
  argv_text.insert(argv_text.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : argv_text)
    argv.push_back(a.data());
  argv.push_back(nullptr);

  // `extra_env` replaces a variable of the same name (getenv would find the first of two).
  const auto named_in_extra = [&extra_env](std::string_view entry) {
    const std::string_view name = entry.substr(0, entry.find('='));
    for (const std::string& x : extra_env)
      if (std::string_view(x).substr(0, x.find('=')) == name) return true;
    return false;
  };
  std::vector<std::string> env_text;
  for (char** e = environ; *e != nullptr; ++e)
    if (!named_in_extra(*e)) env_text.emplace_back(*e);
  env_text.insert(env_text.end(), extra_env.begin(), extra_env.end());
  std::vector<char*> envp;
  for (std::string& e : env_text)
    envp.push_back(e.data());
  envp.push_back(nullptr);

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  const std::string out = (dir_ / "stdout").string(), err = (dir_ / "stderr").string();
  posix_spawn_file_actions_addopen(&actions, 1, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&actions, 2, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  // Its own process group (killed as a whole on failure), and no signal blocked or ignored.
  sigset_t none;
  sigemptyset(&none);
  posix_spawnattr_setsigmask(&attr, &none);
  posix_spawnattr_setpgroup(&attr, 0);
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETPGROUP | POSIX_SPAWN_SETSIGMASK);
  const int error = posix_spawn(&pid_, argv[0], &actions, &attr, argv.data(), envp.data());
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attr);
  if (error != 0) throw std::runtime_error("cannot start " + program);
}

RigiddProcess::~RigiddProcess() {
  if (running()) {
    ::kill(-pid_, SIGKILL);
    int status = 0;
    ::waitpid(pid_, &status, 0);
  }
  std::error_code ec;
  std::filesystem::remove_all(dir_, ec);
}

void RigiddProcess::signal(int sig) const {
  if (!status_) ::kill(pid_, sig);
}

std::optional<int> RigiddProcess::wait_exit(std::chrono::milliseconds patience) {
  if (status_) return status_;
  const auto deadline = std::chrono::steady_clock::now() + patience;
  for (;;) {
    int status = 0;
    const pid_t done = ::waitpid(pid_, &status, WNOHANG);
    if (done == pid_) {
      status_ = status;
      return status_;
    }
    if (std::chrono::steady_clock::now() >= deadline) return std::nullopt;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
}

int RigiddProcess::terminate(std::chrono::milliseconds patience) {
  const auto t0 = std::chrono::steady_clock::now();
  signal(SIGTERM);
  const std::optional<int> status = wait_exit(patience);
  stop_time_ =
      std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - t0);
  if (!status) {
    ::kill(-pid_, SIGKILL);
    wait_exit(std::chrono::milliseconds(5000));
    return -1;
  }
  return WIFEXITED(*status) ? WEXITSTATUS(*status) : -1;
}

std::string RigiddProcess::stderr_text() const {
  return read(dir_ / "stderr");
}

std::string RigiddProcess::stdout_text() const {
  return read(dir_ / "stdout");
}

Completed run_to_exit(const std::vector<std::string>& args, std::chrono::milliseconds patience) {
  return run_program_to_exit(RIGIDD_EXE, args, patience);
}

Completed run_program_to_exit(const std::string& program, const std::vector<std::string>& args,
                              std::chrono::milliseconds patience) {
  RigiddProcess p(program, args, {});
  Completed c;
  const std::optional<int> status = p.wait_exit(patience);
  if (status && WIFEXITED(*status)) c.exit_code = WEXITSTATUS(*status);
  c.out = p.stdout_text();
  c.err = p.stderr_text();
  return c;
}

int count_lines(const std::string& text) {
  int n = 0;
  for (char c : text)
    n += c == '\n';
  return n;
}

}  // namespace rigid::rigidd::testing
