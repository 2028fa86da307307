// One line per event, from any thread. Lines from different threads never interleave: each is
// written with a single write(2). The loop thread never logs (it would allocate and could block);
// it leaves events for the housekeeping thread (see reject_counters.hpp).
#pragma once

#include <mutex>
#include <string>
#include <string_view>
#include <vector>

namespace rigid::loop {

class Log {
 public:
  virtual ~Log() = default;
  // `text` is one line without its newline.
  virtual void line(std::string_view text) = 0;
};

// Writes "PREFIX: text\n" to a file descriptor (stderr by default).
class FdLog final : public Log {
 public:
  explicit FdLog(std::string prefix, int fd = 2) : prefix_(std::move(prefix)), fd_(fd) {}
  void line(std::string_view text) override;

 private:
  std::string prefix_;
  int fd_;
};

// Keeps the lines, for tests.
class MemoryLog final : public Log {
 public:
  void line(std::string_view text) override;
  std::vector<std::string> lines() const;

 private:
  mutable std::mutex mutex_;
  std::vector<std::string> lines_;
};

}  // namespace rigid::loop
