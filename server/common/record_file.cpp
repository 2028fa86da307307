#include "common/record_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

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

std::string system_error(const std::string& path, const std::string& what) {
  return path + ": " + what + ": " + std::strerror(errno);
}

// lcm-logger's event sync word, big-endian, at the start of every event.
constexpr std::array<std::uint8_t, 4> kLcmSync{0xED, 0xA1, 0xDA, 0x01};

}  // namespace

std::string software_version() {
  return "rigid " RIGID_VERSION;
}

RecordWriter::RecordWriter(const std::string& path, bool overwrite) : path_(path) {
  const int flags = O_WRONLY | O_CREAT | O_CLOEXEC | (overwrite ? O_TRUNC : O_EXCL);
  fd_ = ::open(path.c_str(), flags, 0644);
  if (fd_ < 0) {
    if (errno == EEXIST) {
      throw LogFileError(path + ": exists (remove it or choose another name)");
    }
    throw LogFileError(system_error(path, "cannot create"));
  }
  buffer_.reserve(kBufferBytes + 4096);
  buffer_.append(kLogMagic);
  put_u32(buffer_, kLogFormatVersion);
  bytes_ = buffer_.size();
}

RecordWriter::~RecordWriter() {
  try {
    close();
  } catch (const LogFileError&) {
    // Already reported by whoever wrote last; nothing better to do in a destructor.
  }
}

void RecordWriter::append(const msgs::LogRecord& record) {
  if (fd_ < 0) throw LogFileError(path_ + ": written after close");
  payload_.clear();
  if (!record.SerializeToString(&payload_) || payload_.size() > kMaxRecordBytes) {
    throw LogFileError(path_ + ": a record of " + std::to_string(payload_.size()) +
                       " bytes cannot be written");
  }
  const std::size_t start = buffer_.size();
  put_u32(buffer_, static_cast<std::uint32_t>(payload_.size()));
  const std::uint32_t crc =
      crc32c(bytes_of(payload_), crc32c(bytes_of(std::string_view(buffer_).substr(start, 4))));
  put_u32(buffer_, crc);
  buffer_.append(payload_);
  bytes_ += kFrameHeaderBytes + payload_.size();
  ++records_;
  if (buffer_.size() >= kBufferBytes) flush();
}

void RecordWriter::write_out(std::string_view bytes) {
  while (!bytes.empty()) {
    const ssize_t n = ::write(fd_, bytes.data(), bytes.size());
    if (n < 0) {
      if (errno == EINTR) continue;
      throw LogFileError(system_error(path_, "cannot write"));
    }
    bytes.remove_prefix(static_cast<std::size_t>(n));
  }
}

void RecordWriter::flush() {
  if (fd_ < 0 || buffer_.empty()) return;
  // Cleared before writing: after a failed write the buffer would repeat bytes already written.
  std::string pending;
  pending.swap(buffer_);
  buffer_.reserve(kBufferBytes + 4096);
  write_out(pending);
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
  if (!synced || !closed) throw LogFileError(system_error(path_, "cannot close"));
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
  const std::uint32_t version = get_u32(preamble.data() + kLogMagic.size());
  if (version != kLogFormatVersion) {
    throw LogFileError(path + ": log format version " + std::to_string(version) +
                       ", this program reads version " + std::to_string(kLogFormatVersion));
  }
  offset_ = kLogPreambleBytes;
}

bool RecordReader::fail(std::string reason) {
  damage_ = Damage{offset_, size_ - offset_, std::move(reason)};
  return false;
}

bool RecordReader::next(msgs::LogRecord& out) {
  if (damage_ || offset_ >= size_) return false;
  const std::uint64_t left = size_ - offset_;
  std::array<std::uint8_t, kFrameHeaderBytes> header{};
  if (left < header.size()) {
    return fail("frame header cut short: " + std::to_string(left) + " of 8 bytes");
  }
  if (std::fread(header.data(), 1, header.size(), file_.get()) != header.size()) {
    return fail("cannot read: " + std::string(std::strerror(errno)));
  }
  const std::uint32_t length = get_u32(header.data());
  const std::uint32_t expected = get_u32(header.data() + 4);
  if (length > kMaxRecordBytes) {
    return fail("implausible record length " + std::to_string(length) + " (corrupted frame)");
  }
  if (length > left - header.size()) {
    return fail("record cut short: " + std::to_string(left - header.size()) + " of " +
                std::to_string(length) + " bytes");
  }
  payload_.resize(length);
  if (std::fread(payload_.data(), 1, length, file_.get()) != length) {
    return fail("cannot read: " + std::string(std::strerror(errno)));
  }
  const std::uint32_t crc =
      crc32c(bytes_of(payload_), crc32c(std::span<const std::uint8_t>(header.data(), 4)));
  if (crc != expected) return fail("checksum mismatch (corrupted record)");
  if (!out.ParseFromString(payload_)) {
    return fail("checksum correct but the record does not parse (written by another schema?)");
  }
  offset_ += header.size() + length;
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
