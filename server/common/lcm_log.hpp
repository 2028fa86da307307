// Reads the event logs lcm-logger writes, so that rigid-record export and rigid-view can read an
// LCM user's existing recordings. The format (LCM's documented log format): a sequence of events,
// each
//
//   uint32 sync word 0xEDA1DA01, int64 event number, int64 timestamp (us since the epoch),
//   int32 channel length, int32 data length, the channel's bytes, the data's bytes
//
// all big-endian. Like record_file.hpp's reader, it stops at the first event that is cut short or
// does not start with the sync word and reports the rest as a damaged tail.
#pragma once

#include <cstdint>
#include <cstdio>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/record_file.hpp"

namespace rigid::common {

struct LcmEvent {
  std::int64_t number = 0;
  std::int64_t timestamp_us = 0;
  std::string channel;
  std::vector<std::uint8_t> data;
};

class LcmLogReader {
 public:
  // Throws common::LogFileError when the file cannot be opened or is not an LCM log.
  explicit LcmLogReader(const std::string& path);
  // The next complete event, or false: at the end, or at damage (damage() says where and why).
  bool next(LcmEvent& out);
  const std::optional<common::Damage>& damage() const { return damage_; }
  std::int64_t events() const { return events_; }

 private:
  bool fail(std::string reason);

  struct Close {
    void operator()(std::FILE* f) const { std::fclose(f); }
  };
  std::string path_;
  std::unique_ptr<std::FILE, Close> file_;
  std::uint64_t size_ = 0;
  std::uint64_t offset_ = 0;
  std::int64_t events_ = 0;
  std::optional<common::Damage> damage_;
};

// The prefix of rigidd's channels in an LCM log whose channels (with their event counts) are
// `seen`: `prefix` if given, else "" if the unprefixed state channel is there, else the one prefix
// the log holds. Throws SeveralPrefixes, or LogFileError when there is none.
class SeveralPrefixes : public LogFileError {
 public:
  using LogFileError::LogFileError;
};
std::string lcm_log_prefix(const std::string& file, const std::optional<std::string>& prefix,
                           const std::map<std::string, std::int64_t>& seen);

}  // namespace rigid::common
