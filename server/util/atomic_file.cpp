// Write-then-rename output files.
#include "util/atomic_file.hpp"

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace rigid::util {

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)), tmp_(path_ + ".tmp") {
  file_.reset(std::fopen(tmp_.c_str(), "wb"));
  if (!file_) {
    throw std::runtime_error("cannot create " + tmp_ + ": " + std::strerror(errno));
  }
}

AtomicFile::~AtomicFile() {
  if (!committed_) {
    file_.reset();
    std::remove(tmp_.c_str());
  }
}

void AtomicFile::fail(const std::string& what) {
  const std::string reason = std::strerror(errno);
  file_.reset();
  std::remove(tmp_.c_str());
  committed_ = true;  // nothing left to clean up
  throw std::runtime_error(what + ": " + reason);
}

void AtomicFile::write(std::string_view bytes) {
  if (!file_) throw std::logic_error("AtomicFile::write after commit");
  if (std::fwrite(bytes.data(), 1, bytes.size(), file_.get()) != bytes.size()) {
    fail("cannot write " + tmp_);
  }
}

void AtomicFile::commit() {
  if (!file_) throw std::logic_error("AtomicFile::commit twice");
  if (std::fflush(file_.get()) != 0 || std::ferror(file_.get()) != 0) fail("cannot write " + tmp_);
  // fclose can report a deferred write error (e.g. a full disk on NFS), so check it too.
  if (std::fclose(file_.release()) != 0) fail("cannot write " + tmp_);
  if (std::rename(tmp_.c_str(), path_.c_str()) != 0) {
    fail("cannot rename " + tmp_ + " to " + path_);
  }
  committed_ = true;
}

}  // namespace rigid::util
