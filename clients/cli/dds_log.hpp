// Cyclone DDS's own log lines kept out of a tool's output, for the tool to say in its own words
// what went wrong. Cyclone writes its errors and warnings to stderr with a timestamp and a domain
// number ("1796681516.08 [17] fsm: Begin handshake reply failed: ..."), several a second while a
// DDS Security handshake keeps failing; a tool that lets them through buries its own one-line
// answer. While a DdsLog lives, Cyclone gives them to it instead (its Tracing settings in
// CYCLONEDDS_URI still write them to a trace file), and the tool reads from it:
//
//   - the identity this process runs as was refused when joining (expired, revoked, from another
//     keystore): Cyclone says why when the participant cannot be created;
//   - the handshake with another participant failed (rigidd's certificate is not from this
//     identity's keystore, or the other way round);
//   - the last error, to add to a bus error (a network interface that does not exist).
//
// Cyclone's log sink is one per process: make one DdsLog in main(), before any bus.
#pragma once

#include <deque>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>

#include "rigid/client/bus.hpp"

namespace rigid::clients {

class DdsLog {
 public:
  DdsLog();
  ~DdsLog();  // gives Cyclone its own sink back
  DdsLog(const DdsLog&) = delete;
  DdsLog& operator=(const DdsLog&) = delete;

  struct SecurityFailure {
    bool handshake = false;  // with another participant; false: this process's own identity
    std::string reason;      // e.g. "Certificate not valid: certificate revoked; subject: /CN=x"
  };
  // The last DDS Security failure Cyclone reported, if any.
  std::optional<SecurityFailure> security_failure() const;
  // The last line Cyclone logged, without its timestamp (empty: none).
  std::string last_line() const;

  // Takes one line as Cyclone gives it. Public for the tests; Cyclone calls it through the sink.
  void take(std::string_view line);

  static constexpr std::size_t kMaxLineBytes = 512;

 private:
  mutable std::mutex mutex_;
  std::string last_;
  std::optional<SecurityFailure> failure_;
};

// What a tool says after its own words when no rigidd answered on `bus`: where to look, or, when
// DDS Security authentication failed, that it did and why.
std::string no_rigidd_hint(const client::BusOptions& bus, const DdsLog& log);

// A bus that could not be set up (BusError's one line), with what Cyclone said about it: the
// reason an identity was refused, or its last error.
std::string bus_error_line(const std::string& what, const client::BusOptions& bus,
                           const DdsLog& log);

}  // namespace rigid::clients
