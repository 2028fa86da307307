#include "util/signal_watcher.hpp"

#include <poll.h>
#include <pthread.h>
#include <sys/signalfd.h>
#include <unistd.h>

#include <cerrno>
#include <system_error>

namespace rigid::util {

SignalWatcher::SignalWatcher(std::initializer_list<int> signals) {
  sigemptyset(&set_);
  for (int s : signals)
    sigaddset(&set_, s);
  if (const int error = pthread_sigmask(SIG_BLOCK, &set_, &previous_); error != 0) {
    throw std::system_error(error, std::generic_category(), "cannot block signals");
  }
  fd_ = signalfd(-1, &set_, SFD_CLOEXEC);
  if (fd_ < 0) {
    const int error = errno;
    pthread_sigmask(SIG_SETMASK, &previous_, nullptr);
    throw std::system_error(error, std::generic_category(), "cannot open a signalfd");
  }
}

SignalWatcher::~SignalWatcher() {
  ::close(fd_);
  pthread_sigmask(SIG_SETMASK, &previous_, nullptr);
}

std::optional<int> SignalWatcher::wait(std::chrono::milliseconds timeout) {
  pollfd p{fd_, POLLIN, 0};
  const int n = ::poll(&p, 1, static_cast<int>(timeout.count()));
  if (n <= 0 || (p.revents & POLLIN) == 0) return std::nullopt;
  signalfd_siginfo info{};
  if (::read(fd_, &info, sizeof info) != static_cast<ssize_t>(sizeof info)) return std::nullopt;
  return static_cast<int>(info.ssi_signo);
}

}  // namespace rigid::util
