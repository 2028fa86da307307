#include "common/record_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zstd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>

#include "common/crc32c.hpp"

namespace rigid::common {
namespace {

void put_u32(std::string& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i)
    out.push_back(static_cast<char>((v >> (8 * i)) & 0xFF));
}

std::uint32_t get_u32(const std::uint8_t* p) {
  return static_cast<std::uint32_t>(p[0]) | static_cast<std::uint32_t>(p[1]) << 8 |
         static_cast<std::uint32_t>(p[2]) << 16 | static_cast<std::uint32_t>(p[3]) << 24;
}

std::span<const std::uint8_t> bytes_of(std::string_view s) {
  return {reinterpret_cast<const std::uint8_t*>(s.data()), s.size()};
}

// A frame's header: the length word and the CRC-32C of it and the payload.
void put_frame_header(std::string& out, std::uint32_t length_word, std::string_view payload) {
  const std::size_t start = out.size();
  put_u32(out, length_word);
  const std::uint32_t crc =
      crc32c(bytes_of(payload), crc32c(bytes_of(std::string_view(out).substr(start, 4))));
  put_u32(out, crc);
}

std::string system_error(const std::string& path, const std::string& what) {
  return path + ": " + what + ": " + std::strerror(errno);
}

bool disk_full(int error) {
  return error == ENOSPC || error == EDQUOT || error == EFBIG;
}

// lcm-logger's event sync word, big-endian, at the start of every event.
constexpr std::array<std::uint8_t, 4> kLcmSync{0xED, 0xA1, 0xDA, 0x01};

}  // namespace

std::string software_version() {
  return "rigid " RIGID_VERSION;
}

void RecordWriter::FreeCctx::operator()(void* c) const {
  ZSTD_freeCCtx(static_cast<ZSTD_CCtx*>(c));
}

RecordWriter::RecordWriter(const std::string& path, bool overwrite, Compression compression)
    : path_(path), compression_(compression) {
  if (compression_.zstd) {
    if (compression_.level < 1 || compression_.level > ZSTD_maxCLevel()) {
      throw LogFileError(path + ": zstd level " + std::to_string(compression_.level) +
                         " is not in 1 .. " + std::to_string(ZSTD_maxCLevel()));
    }
    cctx_.reset(ZSTD_createCCtx());
    if (!cctx_ ||
        ZSTD_isError(ZSTD_CCtx_setParameter(static_cast<ZSTD_CCtx*>(cctx_.get()),
                                            ZSTD_c_compressionLevel, compression_.level)) ||
        // The chunk's frame states its size: the reader checks it before allocating.
        ZSTD_isError(ZSTD_CCtx_setParameter(static_cast<ZSTD_CCtx*>(cctx_.get()),
                                            ZSTD_c_contentSizeFlag, 1))) {
      throw LogFileError(path + ": cannot set up zstd compression");
    }
  }
  const int flags = O_WRONLY | O_CREAT | O_CLOEXEC | (overwrite ? O_TRUNC : O_EXCL);
  fd_ = ::open(path.c_str(), flags, 0644);
  if (fd_ < 0) {
    if (errno == EEXIST) {
      throw FileExistsError(path + ": exists (remove it or choose another name)");
    }
    throw LogFileError(system_error(path, "cannot create"));
  }
  buffer_.reserve(kBufferBytes + 4096);
  buffer_.append(kLogMagic);
  put_u32(buffer_, compression_.zstd ? kLogFormatChunked : kLogFormatVersion);
  frame_ends_.emplace_back(buffer_.size(), 0);
  bytes_ = buffer_.size();
}

RecordWriter::~RecordWriter() {
  try {
    close();
  } catch (const LogFileError&) {
    // Already reported by whoever wrote last; nothing better to do in a destructor.
  }
}

void RecordWriter::add_frame(std::string_view payload, bool chunk, std::int64_t records) {
  const auto length = static_cast<std::uint32_t>(payload.size());
  put_frame_header(buffer_, chunk ? (length | kChunkFlag) : length, payload);
  buffer_.append(payload);
  frame_ends_.emplace_back(buffer_.size(), records);
  bytes_ += kFrameHeaderBytes + payload.size();
}

void RecordWriter::append(const msgs::LogRecord& record) {
  if (fd_ < 0 || failed_) throw LogFileError(path_ + ": written after close or a failed write");
  payload_.clear();
  if (!record.SerializeToString(&payload_) || payload_.size() > kMaxRecordBytes) {
    throw LogFileError(path_ + ": a record of " + std::to_string(payload_.size()) +
                       " bytes cannot be written");
  }
  ++records_;
  record_bytes_ += kFrameHeaderBytes + payload_.size();
  if (!compression_.zstd) {
    add_frame(payload_, false, 1);
  } else {
    // A chunk holds at most kChunkBytes of frames, or one larger record alone.
    if (!chunk_.empty() && chunk_.size() + kFrameHeaderBytes + payload_.size() > kChunkBytes) {
      seal_chunk();
    }
    put_frame_header(chunk_, static_cast<std::uint32_t>(payload_.size()), payload_);
    chunk_.append(payload_);
    ++chunk_records_;
    if (chunk_.size() >= kChunkBytes) seal_chunk();
  }
  if (buffer_.size() >= kBufferBytes) write_buffer();
}

void RecordWriter::seal_chunk() {
  if (chunk_.empty()) return;
  auto* cctx = static_cast<ZSTD_CCtx*>(cctx_.get());
  compressed_.resize(ZSTD_compressBound(chunk_.size()));
  const std::size_t n =
      ZSTD_compress2(cctx, compressed_.data(), compressed_.size(), chunk_.data(), chunk_.size());
  if (!ZSTD_isError(n) && n + kFrameHeaderBytes < chunk_.size() && n <= kMaxRecordBytes) {
    compressed_.resize(n);
    add_frame(compressed_, true, chunk_records_);
  } else {
    // It would not shrink (or zstd failed): the frames go out as they are, each readable alone.
    std::size_t at = 0;
    while (at < chunk_.size()) {
      const std::size_t frame =
          kFrameHeaderBytes + get_u32(reinterpret_cast<const std::uint8_t*>(chunk_.data() + at));
      buffer_.append(chunk_, at, frame);
      frame_ends_.emplace_back(buffer_.size(), 1);
      bytes_ += frame;
      at += frame;
    }
  }
  chunk_.clear();
  chunk_records_ = 0;
}

bool RecordWriter::write_all(std::string_view bytes, std::size_t& written) {
  written = 0;
  while (written < bytes.size()) {
    const ssize_t n = ::write(fd_, bytes.data() + written, bytes.size() - written);
    if (n < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    written += static_cast<std::size_t>(n);
  }
  return true;
}

void RecordWriter::write_buffer() {
  if (fd_ < 0 || failed_ || buffer_.empty()) return;
  std::size_t written = 0;
  if (write_all(buffer_, written)) {
    written_ += buffer_.size();
    for (const auto& frame : frame_ends_)
      records_written_ += frame.second;
    buffer_.clear();
    frame_ends_.clear();
    return;
  }
  const int error = errno;
  failed_ = true;
  // Cut the file back to the last frame that went out whole, so that it ends cleanly there.
  std::size_t keep = 0;
  for (const auto& [end, records] : frame_ends_) {
    if (end > written) break;
    keep = end;
    records_written_ += records;
  }
  const auto length = static_cast<off_t>(written_ + keep);
  const bool cut = ::ftruncate(fd_, length) == 0;
  written_ += keep;
  bytes_ = written_;
  buffer_.clear();
  frame_ends_.clear();
  errno = error;
  if (disk_full(error)) {
    throw DiskFullError(path_ + ": " + std::strerror(error) + " after " + std::to_string(written_) +
                        " bytes" +
                        (cut ? "" : " (and the partial record at its end could not be cut off)"));
  }
  throw LogFileError(system_error(path_, "cannot write"));
}

void RecordWriter::flush() {
  if (fd_ < 0 || failed_) return;
  if (compression_.zstd) seal_chunk();
  write_buffer();
}

void RecordWriter::close() {
  if (fd_ < 0) return;
  const int fd = fd_;
  try {
    flush();
  } catch (const LogFileError&) {
    ::close(fd);
    fd_ = -1;
    throw;
  }
  fd_ = -1;
  const bool synced = ::fdatasync(fd) == 0;
  const bool closed = ::close(fd) == 0;
  if (failed_) return;  // reported by the write that failed
  if (!synced || !closed) {
    if (disk_full(errno)) throw DiskFullError(system_error(path_, "cannot close"));
    throw LogFileError(system_error(path_, "cannot close"));
  }
}

void RecordReader::FreeDctx::operator()(void* d) const {
  ZSTD_freeDCtx(static_cast<ZSTD_DCtx*>(d));
}

RecordReader::RecordReader(const std::string& path) : path_(path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) throw LogFileError(system_error(path, "cannot open"));
  if (S_ISDIR(st.st_mode)) throw LogFileError(path + ": is a directory, not a log file");
  file_.reset(std::fopen(path.c_str(), "rb"));
  if (!file_) throw LogFileError(system_error(path, "cannot open"));
  size_ = static_cast<std::uint64_t>(st.st_size);
  std::array<std::uint8_t, kLogPreambleBytes> preamble{};
  const std::size_t got = std::fread(preamble.data(), 1, preamble.size(), file_.get());
  if (got >= kLcmSync.size() && std::equal(kLcmSync.begin(), kLcmSync.end(), preamble.begin())) {
    throw LogFileError(path +
                       ": an lcm-logger file, not a rigid log (rigid-record export reads "
                       "both)");
  }
  if (got < kLogMagic.size() ||
      std::memcmp(preamble.data(), kLogMagic.data(), kLogMagic.size()) != 0) {
    throw LogFileError(path + ": not a rigid log file (it does not start with " +
                       std::string(kLogMagic) + ")");
  }
  if (got < preamble.size()) throw LogFileError(path + ": cut short inside its preamble");
  format_ = get_u32(preamble.data() + kLogMagic.size());
  if (format_ != kLogFormatVersion && format_ != kLogFormatChunked) {
    throw LogFileError(path + ": log format version " + std::to_string(format_) +
                       ", this program reads versions " + std::to_string(kLogFormatVersion) +
                       " and " + std::to_string(kLogFormatChunked) + " (a newer rigid wrote it?)");
  }
  offset_ = kLogPreambleBytes;
}

RecordReader::~RecordReader() = default;

bool RecordReader::fail(std::string reason) {
  damage_ = Damage{offset_, size_ - offset_, std::move(reason)};
  chunk_.clear();
  chunk_at_ = 0;
  return false;
}

bool RecordReader::next(msgs::LogRecord& out) {
  if (damage_) return false;
  if (chunk_at_ < chunk_.size()) return next_in_chunk(out);
  if (offset_ >= size_) return false;
  const std::uint64_t left = size_ - offset_;
  std::array<std::uint8_t, kFrameHeaderBytes> header{};
  if (left < header.size()) {
    return fail("frame header cut short: " + std::to_string(left) + " of 8 bytes");
  }
  if (std::fread(header.data(), 1, header.size(), file_.get()) != header.size()) {
    return fail("cannot read: " + std::string(std::strerror(errno)));
  }
  const std::uint32_t word = get_u32(header.data());
  // Format 1 has no chunks: there the flag is an implausible length, as it always was.
  const bool chunk = format_ == kLogFormatChunked && (word & kChunkFlag) != 0;
  const std::uint32_t length = chunk ? word & ~kChunkFlag : word;
  const std::uint32_t expected = get_u32(header.data() + 4);
  if (length > kMaxRecordBytes) {
    return fail("implausible record length " + std::to_string(length) + " (corrupted frame)");
  }
  if (length > left - header.size()) {
    return fail(std::string(chunk ? "chunk" : "record") + " cut short: " +
                std::to_string(left - header.size()) + " of " + std::to_string(length) + " bytes");
  }
  payload_.resize(length);
  if (std::fread(payload_.data(), 1, length, file_.get()) != length) {
    return fail("cannot read: " + std::string(std::strerror(errno)));
  }
  const std::uint32_t crc =
      crc32c(bytes_of(payload_), crc32c(std::span<const std::uint8_t>(header.data(), 4)));
  if (crc != expected) {
    return fail(std::string("checksum mismatch (corrupted ") + (chunk ? "chunk)" : "record)"));
  }
  if (chunk) {
    if (!open_chunk(length)) return false;
    return next_in_chunk(out);
  }
  if (!out.ParseFromString(payload_)) {
    return fail("checksum correct but the record does not parse (written by another schema?)");
  }
  offset_ += header.size() + length;
  ++records_;
  return true;
}

bool RecordReader::open_chunk(std::uint32_t length) {
  const unsigned long long size = ZSTD_getFrameContentSize(payload_.data(), payload_.size());
  if (size == ZSTD_CONTENTSIZE_ERROR) return fail("a chunk that is not a zstd frame");
  if (size == ZSTD_CONTENTSIZE_UNKNOWN) return fail("a chunk whose zstd frame omits its size");
  if (size == 0 || size > kMaxChunkBytes) {
    return fail("implausible chunk size " + std::to_string(size) + " (corrupted chunk)");
  }
  if (ZSTD_findFrameCompressedSize(payload_.data(), payload_.size()) != payload_.size()) {
    return fail("a chunk with bytes after its zstd frame (corrupted chunk)");
  }
  if (!dctx_) {
    dctx_.reset(ZSTD_createDCtx());
    if (!dctx_) return fail("cannot set up zstd decompression");
  }
  chunk_.resize(static_cast<std::size_t>(size));
  const std::size_t n = ZSTD_decompressDCtx(static_cast<ZSTD_DCtx*>(dctx_.get()), chunk_.data(),
                                            chunk_.size(), payload_.data(), payload_.size());
  if (ZSTD_isError(n) || n != chunk_.size()) {
    return fail(std::string("a chunk that does not decompress (") +
                (ZSTD_isError(n) ? ZSTD_getErrorName(n) : "shorter than it says") + ")");
  }
  // Every frame inside, before the first record is returned: a chunk is read whole or not at all.
  const auto* bytes = reinterpret_cast<const std::uint8_t*>(chunk_.data());
  std::size_t at = 0;
  while (at < chunk_.size()) {
    const std::size_t left = chunk_.size() - at;
    if (left < kFrameHeaderBytes) return fail("a chunk that ends inside a frame header");
    const std::uint32_t inner = get_u32(bytes + at);
    if (inner > left - kFrameHeaderBytes) {
      return fail("a chunk that ends inside a record (" + std::to_string(inner) + " bytes)");
    }
    const std::uint32_t crc =
        crc32c(std::span<const std::uint8_t>(bytes + at + kFrameHeaderBytes, inner),
               crc32c(std::span<const std::uint8_t>(bytes + at, 4)));
    if (crc != get_u32(bytes + at + 4)) return fail("checksum mismatch inside a chunk");
    at += kFrameHeaderBytes + inner;
  }
  chunk_at_ = 0;
  chunk_end_ = offset_ + kFrameHeaderBytes + length;
  ++chunks_;
  chunk_bytes_ += length;
  chunk_record_bytes_ += chunk_.size();
  return true;
}

bool RecordReader::next_in_chunk(msgs::LogRecord& out) {
  const auto* bytes = reinterpret_cast<const std::uint8_t*>(chunk_.data());
  const std::uint32_t length = get_u32(bytes + chunk_at_);
  if (!out.ParseFromArray(bytes + chunk_at_ + kFrameHeaderBytes, static_cast<int>(length))) {
    return fail("a record in the chunk here does not parse (written by another schema?)");
  }
  chunk_at_ += kFrameHeaderBytes + length;
  if (chunk_at_ == chunk_.size()) {
    offset_ = chunk_end_;
    chunk_.clear();
    chunk_at_ = 0;
  }
  ++records_;
  return true;
}

bool looks_like_lcm_log(const std::string& path) {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!f) return false;
  std::array<std::uint8_t, 4> head{};
  return std::fread(head.data(), 1, head.size(), f.get()) == head.size() && head == kLcmSync;
}

}  // namespace rigid::common
