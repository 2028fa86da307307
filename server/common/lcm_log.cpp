#include "common/lcm_log.hpp"

#include <sys/stat.h>

#include <array>
#include <cerrno>
#include <cstring>

#include "transport/topic.hpp"

namespace rigid::common {
namespace {

constexpr std::uint32_t kSync = 0xEDA1DA01;
constexpr std::size_t kHeaderBytes = 4 + 8 + 8 + 4 + 4;
// LCM's UDP transports carry at most 2^28 bytes a message; longer is damage.
constexpr std::int32_t kMaxData = 1 << 28;
constexpr std::int32_t kMaxChannel = 1 << 12;

std::uint64_t big_endian(const std::uint8_t* p, int bytes) {
  std::uint64_t v = 0;
  for (int i = 0; i < bytes; ++i)
    v = (v << 8) | p[i];
  return v;
}

}  // namespace

LcmLogReader::LcmLogReader(const std::string& path) : path_(path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    throw common::LogFileError(path + ": cannot open: " + std::strerror(errno));
  }
  file_.reset(std::fopen(path.c_str(), "rb"));
  if (!file_) throw common::LogFileError(path + ": cannot open: " + std::strerror(errno));
  size_ = static_cast<std::uint64_t>(st.st_size);
  if (!common::looks_like_lcm_log(path)) {
    throw common::LogFileError(path + ": not an lcm-logger file (no event sync word)");
  }
}

bool LcmLogReader::fail(std::string reason) {
  damage_ = common::Damage{offset_, size_ - offset_, std::move(reason)};
  return false;
}

bool LcmLogReader::next(LcmEvent& out) {
  if (damage_ || offset_ >= size_) return false;
  const std::uint64_t left = size_ - offset_;
  std::array<std::uint8_t, kHeaderBytes> h{};
  if (left < h.size()) {
    return fail("event header cut short: " + std::to_string(left) + " of " +
                std::to_string(h.size()) + " bytes");
  }
  if (std::fread(h.data(), 1, h.size(), file_.get()) != h.size()) {
    return fail(std::string("cannot read: ") + std::strerror(errno));
  }
  if (big_endian(h.data(), 4) != kSync) return fail("no sync word (corrupted event)");
  const auto channel_bytes = static_cast<std::int32_t>(big_endian(h.data() + 20, 4));
  const auto data_bytes = static_cast<std::int32_t>(big_endian(h.data() + 24, 4));
  if (channel_bytes < 0 || channel_bytes > kMaxChannel || data_bytes < 0 || data_bytes > kMaxData) {
    return fail("implausible lengths (corrupted event)");
  }
  const std::uint64_t body = static_cast<std::uint64_t>(channel_bytes) + data_bytes;
  if (body > left - h.size()) {
    return fail("event cut short: " + std::to_string(left - h.size()) + " of " +
                std::to_string(body) + " bytes");
  }
  out.number = static_cast<std::int64_t>(big_endian(h.data() + 4, 8));
  out.timestamp_us = static_cast<std::int64_t>(big_endian(h.data() + 12, 8));
  out.channel.resize(static_cast<std::size_t>(channel_bytes));
  out.data.resize(static_cast<std::size_t>(data_bytes));
  if (std::fread(out.channel.data(), 1, out.channel.size(), file_.get()) != out.channel.size() ||
      std::fread(out.data.data(), 1, out.data.size(), file_.get()) != out.data.size()) {
    return fail(std::string("cannot read: ") + std::strerror(errno));
  }
  offset_ += h.size() + body;
  ++events_;
  return true;
}

std::string lcm_log_prefix(const std::string& file, const std::optional<std::string>& prefix,
                           const std::map<std::string, std::int64_t>& seen) {
  using transport::Topic;
  const auto state = [](const std::string& prefix) {
    return transport::lcm_channel_names(prefix)[transport::index_of(Topic::kState)];
  };
  if (prefix) return *prefix;
  const std::string plain = state("");
  if (seen.contains(plain)) return "";
  std::vector<std::string> prefixes;
  for (const auto& [channel, n] : seen) {
    if (channel.size() > plain.size() + 1 && channel.ends_with("_" + plain)) {
      prefixes.push_back(channel.substr(0, channel.size() - plain.size() - 1));
    }
  }
  if (prefixes.size() > 1) {
    std::string list;
    for (const std::string& p : prefixes)
      list += (list.empty() ? "" : ", ") + p;
    throw SeveralPrefixes(file + " holds the states of several prefixes (" + list +
                          "): choose one with --prefix");
  }
  if (prefixes.empty()) {
    throw LogFileError(file + ": no " + plain + " channel (of any prefix) in this log");
  }
  return prefixes.front();
}

}  // namespace rigid::common
