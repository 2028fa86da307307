// rigid's log files, recordings (rigid-record) and journals (rigidd --journal): an 8-byte magic
// and a format version, then frames. A frame is
//
//   uint32 length of the payload (little-endian); its top bit set: the payload is a zstd chunk
//   uint32 CRC-32C of those 4 length bytes and the payload (little-endian)
//   payload: one serialized LogRecord (msgs/rigid.proto, "Log records"), or a chunk
//
// written straight to the final file as they come (no temporary file, no index at the end). So a
// writer killed at any instant leaves every frame it handed to the kernel readable: the reader
// stops at the first frame that is cut short or fails its checksum and reports the rest of the
// file as a damaged tail, instead of failing. The length is inside the checksum, so a corrupted
// length is caught as damage rather than sending the reader off into the file.
//
// Format 1 holds record frames only. Format 2 (rigid-record record's default) also holds chunks:
// a chunk is one zstd frame (RFC 8878) that gives its decompressed size and decompresses to
// format 1 record frames, exactly the bytes an uncompressed writer would have written for those
// records (so a writer whose chunk would not shrink writes those frames as they are). A writer
// seals a chunk at kChunkBytes of records and at each flush (every 100 ms in rigid-record), so a
// chunk never holds more than a flush period's records, or one larger record alone. Readers read
// both formats and refuse any other version; a program that only knows format 1 refuses format 2
// files by their version instead of misreading them.
#pragma once

#include <cstdint>
#include <cstdio>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "rigid.pb.h"

namespace rigid::common {

inline constexpr std::string_view kLogMagic = "RIGIDLOG";
inline constexpr std::uint32_t kLogFormatVersion = 1;  // of the framing: records only
inline constexpr std::uint32_t kLogFormatChunked = 2;  // records and zstd chunks of records
inline constexpr std::uint32_t kLogSchemaVersion = 1;  // of the records (LogHeader.schema_version)
inline constexpr std::size_t kLogPreambleBytes = 12;   // magic and format version
inline constexpr std::size_t kFrameHeaderBytes = 8;    // length and checksum
// A length field above this is taken for damage (the largest state, 10^5 bodies, is ~11 MB).
inline constexpr std::uint32_t kMaxRecordBytes = 256u << 20;
// The length field's top bit marks a chunk; the bits below it up to kMaxRecordBytes are the length.
inline constexpr std::uint32_t kChunkFlag = 1u << 31;
// Records a writer gathers before it seals a chunk (decompressed size; a larger record is a chunk
// alone). A chunk that decompresses to more than one record of kMaxRecordBytes and its frame
// header is taken for damage, so a reader holds at most that much of one.
inline constexpr std::size_t kChunkBytes = 1u << 20;
inline constexpr std::size_t kMaxChunkBytes = kMaxRecordBytes + kFrameHeaderBytes;

// "rigid X.Y.Z": the version of the program writing a file (LogHeader.software_version).
std::string software_version();

// A log file that cannot be created, written or opened as one: what() is one line naming the file
// and the reason.
class LogFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The file to create exists and overwriting was not asked for. what() says to remove it or choose
// another name; a program that can overwrite it says how instead.
class FileExistsError : public LogFileError {
 public:
  using LogFileError::LogFileError;
};

// A write that failed because the file system is full (ENOSPC, EDQUOT) or the file reached the
// size limit (EFBIG). The writer has cut the file back to its last complete frame first, so that
// it reads back cleanly up to there (records_written() says how many records that is).
class DiskFullError : public LogFileError {
 public:
  using LogFileError::LogFileError;
};

// How a writer stores records: as they are (format 1), or in zstd chunks (format 2).
struct Compression {
  bool zstd = false;
  int level = 3;  // zstd's level, 1 .. 19 (bench/notes/recording.md compares them)
};

class RecordWriter {
 public:
  // Creates `path` and writes the preamble. An existing file is refused unless `overwrite`.
  // Throws LogFileError (FileExistsError for an existing file).
  RecordWriter(const std::string& path, bool overwrite, Compression compression = {});
  // Flushes and closes; errors are lost (call close() to see them).
  ~RecordWriter();
  RecordWriter(const RecordWriter&) = delete;
  RecordWriter& operator=(const RecordWriter&) = delete;

  // Frames the record into the buffer (or the open chunk), and writes the buffer out once it
  // holds kBufferBytes. Throws LogFileError (DiskFullError when the file system is full; the
  // writer then takes no more records).
  void append(const msgs::LogRecord& record);
  // Seals the open chunk and hands what is buffered to the kernel: from then on it survives the
  // process being killed.
  void flush();
  // Flushes, syncs to the disk and closes. Throws LogFileError. Idempotent; after a failed write
  // it only closes.
  void close();

  const std::string& path() const { return path_; }
  std::int64_t records() const { return records_; }
  // Records in complete frames handed to the kernel (after a DiskFullError: what the file holds).
  std::int64_t records_written() const { return records_written_; }
  // The file's bytes, written and buffered, preamble included (records in the open chunk not yet).
  std::uint64_t bytes() const { return bytes_; }
  // The records' frames before compression (equal to bytes() less the preamble without it).
  std::uint64_t record_bytes() const { return record_bytes_; }

  static constexpr std::size_t kBufferBytes = 64 * 1024;

 private:
  struct FreeCctx {
    void operator()(void* c) const;
  };
  // Appends one frame (header and payload) to the buffer; `records`: how many records it holds.
  void add_frame(std::string_view payload, bool chunk, std::int64_t records);
  void seal_chunk();
  void write_buffer();
  // Writes all of `bytes`; false with errno set on a failure. `written` counts what went out.
  bool write_all(std::string_view bytes, std::size_t& written);

  std::string path_;
  int fd_ = -1;
  bool failed_ = false;  // a write failed: the file was cut back, nothing more is written
  Compression compression_;
  std::unique_ptr<void, FreeCctx> cctx_;
  std::string buffer_;
  // Where each frame in buffer_ ends, and the records up to there (to cut back a partial write).
  std::vector<std::pair<std::size_t, std::int64_t>> frame_ends_;
  std::string chunk_;  // the open chunk's record frames
  std::int64_t chunk_records_ = 0;
  std::string payload_;
  std::string compressed_;
  std::int64_t records_ = 0;
  std::int64_t records_written_ = 0;
  std::uint64_t written_ = 0;  // bytes handed to the kernel
  std::uint64_t bytes_ = 0;
  std::uint64_t record_bytes_ = 0;
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
  // not know (1 and 2 are read).
  explicit RecordReader(const std::string& path);
  ~RecordReader();
  RecordReader(const RecordReader&) = delete;
  RecordReader& operator=(const RecordReader&) = delete;

  // The next complete record, or false: at the end of the file, or at a damaged frame (damage()
  // then says where and why; nothing after it is read). A chunk is checked whole (its checksum,
  // its zstd frame, the frames inside) before its first record is returned; a record inside it
  // that does not parse is damage at the chunk's offset.
  bool next(msgs::LogRecord& out);
  const std::optional<Damage>& damage() const { return damage_; }

  const std::string& path() const { return path_; }
  std::uint32_t format() const { return format_; }
  // Of the next frame: while the records of a chunk are returned, the chunk's own offset, and
  // past the chunk after its last record.
  std::uint64_t offset() const { return offset_; }
  std::uint64_t size() const { return size_; }
  std::int64_t records() const { return records_; }  // read so far
  std::int64_t chunks() const { return chunks_; }    // chunk frames read so far
  // Of the chunks read so far: their compressed payloads and the record frames they held.
  std::uint64_t chunk_bytes() const { return chunk_bytes_; }
  std::uint64_t chunk_record_bytes() const { return chunk_record_bytes_; }

 private:
  struct FreeDctx {
    void operator()(void* d) const;
  };
  bool fail(std::string reason);
  // Decompresses the chunk in payload_ into chunk_ and checks its frames; false on damage.
  bool open_chunk(std::uint32_t length);
  bool next_in_chunk(msgs::LogRecord& out);

  struct Close {
    void operator()(std::FILE* f) const { std::fclose(f); }
  };
  std::string path_;
  std::unique_ptr<std::FILE, Close> file_;
  std::uint32_t format_ = kLogFormatVersion;
  std::uint64_t size_ = 0;
  std::uint64_t offset_ = 0;
  std::int64_t records_ = 0;
  std::string payload_;
  std::optional<Damage> damage_;
  std::unique_ptr<void, FreeDctx> dctx_;
  std::string chunk_;            // the open chunk's record frames
  std::size_t chunk_at_ = 0;     // the next of them
  std::uint64_t chunk_end_ = 0;  // the file offset after the open chunk's frame
  std::int64_t chunks_ = 0;
  std::uint64_t chunk_bytes_ = 0;
  std::uint64_t chunk_record_bytes_ = 0;
};

// True if the file at `path` starts like an lcm-logger event log (its sync word).
bool looks_like_lcm_log(const std::string& path);

}  // namespace rigid::common
