// rigid's log files, recordings (rigid-record) and journals (rigidd --journal): an 8-byte magic
// and a format version, then LogRecord messages (msgs/rigid.proto, "Log records"), each framed as
//
//   uint32 length of the payload (little-endian)
//   uint32 CRC-32C of those 4 length bytes and the payload (little-endian)
//   payload: the serialized LogRecord
//
// written straight to the final file as they come (no temporary file, no index at the end). So a
// writer killed at any instant leaves every record it handed to the kernel readable: the reader
// stops at the first frame that is cut short or fails its checksum and reports the rest of the
// file as a damaged tail, instead of failing. The length is inside the checksum, so a corrupted
// length is caught as damage rather than sending the reader off into the file.
#pragma once

#include <cstdint>
#include <cstdio>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

#include "rigid.pb.h"

namespace rigid::common {

inline constexpr std::string_view kLogMagic = "RIGIDLOG";
inline constexpr std::uint32_t kLogFormatVersion = 1;  // of the framing
inline constexpr std::uint32_t kLogSchemaVersion = 1;  // of the records (LogHeader.schema_version)
inline constexpr std::size_t kLogPreambleBytes = 12;   // magic and format version
inline constexpr std::size_t kFrameHeaderBytes = 8;    // length and checksum
// A length field above this is taken for damage (the largest state, 10^5 bodies, is ~11 MB).
inline constexpr std::uint32_t kMaxRecordBytes = 256u << 20;

// "rigid X.Y.Z": the version of the program writing a file (LogHeader.software_version).
std::string software_version();

// A log file that cannot be created, written or opened as one: what() is one line naming the file
// and the reason.
class LogFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class RecordWriter {
 public:
  // Creates `path` and writes the preamble. An existing file is refused unless `overwrite`.
  // Throws LogFileError.
  RecordWriter(const std::string& path, bool overwrite);
  // Flushes and closes; errors are lost (call close() to see them).
  ~RecordWriter();
  RecordWriter(const RecordWriter&) = delete;
  RecordWriter& operator=(const RecordWriter&) = delete;

  // Frames the record into the buffer, and writes the buffer out once it holds kBufferBytes.
  // Throws LogFileError.
  void append(const msgs::LogRecord& record);
  // Hands what is buffered to the kernel: from then on it survives the process being killed.
  void flush();
  // Flushes, syncs to the disk and closes. Throws LogFileError. Idempotent.
  void close();

  const std::string& path() const { return path_; }
  std::int64_t records() const { return records_; }
  std::uint64_t bytes() const { return bytes_; }  // written and buffered, preamble included

  static constexpr std::size_t kBufferBytes = 64 * 1024;

 private:
  void write_out(std::string_view bytes);

  std::string path_;
  int fd_ = -1;
  std::string buffer_;
  std::string payload_;
  std::int64_t records_ = 0;
  std::uint64_t bytes_ = 0;
};

// Where and why a file stops being readable.
struct Damage {
  std::uint64_t offset = 0;  // of the first byte not read
  std::uint64_t bytes = 0;   // from there to the end of the file
  std::string reason;        // e.g. "record cut short: 1234 of 5678 bytes"
};

class RecordReader {
 public:
  // Opens `path` and checks the preamble. Throws LogFileError: unreadable, not a rigid log file
  // (no magic: "is it an lcm-logger file?" when it looks like one), or a format version it does
  // not know.
  explicit RecordReader(const std::string& path);
  RecordReader(const RecordReader&) = delete;
  RecordReader& operator=(const RecordReader&) = delete;

  // The next complete record, or false: at the end of the file, or at a damaged frame (damage()
  // then says where and why; nothing after it is read).
  bool next(msgs::LogRecord& out);
  const std::optional<Damage>& damage() const { return damage_; }

  const std::string& path() const { return path_; }
  std::uint64_t offset() const { return offset_; }  // of the next frame
  std::uint64_t size() const { return size_; }
  std::int64_t records() const { return records_; }  // read so far

 private:
  bool fail(std::string reason);

  struct Close {
    void operator()(std::FILE* f) const { std::fclose(f); }
  };
  std::string path_;
  std::unique_ptr<std::FILE, Close> file_;
  std::uint64_t size_ = 0;
  std::uint64_t offset_ = 0;
  std::int64_t records_ = 0;
  std::string payload_;
  std::optional<Damage> damage_;
};

// True if the file at `path` starts like an lcm-logger event log (its sync word).
bool looks_like_lcm_log(const std::string& path);

}  // namespace rigid::common
