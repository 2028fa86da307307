// Ownership of an lcm_t (which owns its subscriptions) and of the eventfd that wakes the receive
// thread for shutdown.
#pragma once

#include <lcm/lcm.h>
#include <unistd.h>

#include <memory>
#include <utility>

namespace rigid::transport::lcm {

struct LcmDeleter {
  void operator()(lcm_t* lcm) const { lcm_destroy(lcm); }
};
using LcmHandle = std::unique_ptr<lcm_t, LcmDeleter>;

class FileDescriptor {
 public:
  FileDescriptor() = default;
  explicit FileDescriptor(int fd) : fd_(fd) {}
  ~FileDescriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  FileDescriptor(FileDescriptor&& other) noexcept : fd_(std::exchange(other.fd_, -1)) {}
  FileDescriptor& operator=(FileDescriptor&& other) noexcept {
    if (this != &other) {
      if (fd_ >= 0) ::close(fd_);
      fd_ = std::exchange(other.fd_, -1);
    }
    return *this;
  }
  FileDescriptor(const FileDescriptor&) = delete;
  FileDescriptor& operator=(const FileDescriptor&) = delete;

  int get() const { return fd_; }

 private:
  int fd_ = -1;
};

}  // namespace rigid::transport::lcm
