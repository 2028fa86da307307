#include "loop/log.hpp"

#include <unistd.h>

#include <cerrno>

namespace rigid::loop {

void FdLog::line(std::string_view text) {
  std::string out;
  out.reserve(prefix_.size() + text.size() + 3);
  out.append(prefix_).append(": ").append(text).push_back('\n');
  // One write per line; a short write (a pipe nearly full) continues where it stopped.
  std::string_view rest = out;
  while (!rest.empty()) {
    const ssize_t n = ::write(fd_, rest.data(), rest.size());
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;  // nowhere to log to: losing the line is all we can do
    rest.remove_prefix(static_cast<std::size_t>(n));
  }
}

void MemoryLog::line(std::string_view text) {
  const std::lock_guard lock(mutex_);
  lines_.emplace_back(text);
}

std::vector<std::string> MemoryLog::lines() const {
  const std::lock_guard lock(mutex_);
  return lines_;
}

}  // namespace rigid::loop
