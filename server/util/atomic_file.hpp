// An output file that appears complete or not at all: written to PATH.tmp, renamed to PATH by
// commit(). If the writer is destroyed without commit() (an error, an exception), PATH.tmp is
// removed and PATH is left as it was.
#pragma once

#include <cstdio>
#include <memory>
#include <string>
#include <string_view>

namespace rigid::util {

class AtomicFile {
 public:
  // Creates PATH.tmp. Throws std::runtime_error naming the file and the system's reason.
  explicit AtomicFile(std::string path);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  void write(std::string_view bytes);
  // Flushes, closes and renames PATH.tmp to PATH. Throws std::runtime_error on any failure (then
  // PATH.tmp is removed).
  void commit();

  const std::string& path() const { return path_; }
  const std::string& tmp_path() const { return tmp_; }

 private:
  struct Close {
    void operator()(std::FILE* f) const { std::fclose(f); }
  };
  [[noreturn]] void fail(const std::string& what);

  std::string path_;
  std::string tmp_;
  std::unique_ptr<std::FILE, Close> file_;
  bool committed_ = false;
};

}  // namespace rigid::util
