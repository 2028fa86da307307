#include "cli/dds_log.hpp"

#include <dds/dds.h>

namespace rigid::clients {
namespace {

void sink(void* self, const dds_log_data_t* data) {
  if (data == nullptr || data->message == nullptr) return;
  static_cast<DdsLog*>(self)->take(std::string_view(data->message, data->size));
}

// "Certificate not valid: error: certificate revoked; subject: /CN=x(code: 200)" ->
// "Certificate not valid: certificate revoked; subject: /CN=x".
std::string reason_of(std::string_view text) {
  if (const auto code = text.rfind("(code: "); code != std::string_view::npos) {
    text = text.substr(0, code);
  }
  std::string r(text);
  for (std::size_t at = r.find(": error: "); at != std::string::npos; at = r.find(": error: "))
    r.erase(at + 2, 7);
  while (!r.empty() && (r.back() == ' ' || r.back() == '.'))
    r.pop_back();
  return r;
}

}  // namespace

DdsLog::DdsLog() {
  dds_set_log_sink(&sink, this);
}

DdsLog::~DdsLog() {
  // Synchronous: once it returns no Cyclone thread calls sink() with this.
  dds_set_log_sink(nullptr, nullptr);
}

void DdsLog::take(std::string_view line) {
  // Cyclone gives the message without the timestamp and domain it prints before it.
  while (!line.empty() && (line.back() == '\n' || line.back() == '\r'))
    line.remove_suffix(1);
  line = line.substr(0, kMaxLineBytes);
  // The failures DDS Security reports (Cyclone 0.10's wording): a handshake with another
  // participant ("Begin handshake reply failed: REASON", "Process handshake failed: REASON"), and
  // this process's own identity or permissions when it joins ("Error occurred while validating
  // local permission: REASON").
  std::optional<SecurityFailure> failure;
  if (const auto hs = line.find("handshake"); hs != std::string_view::npos) {
    if (const auto failed = line.find("failed: ", hs); failed != std::string_view::npos) {
      failure = SecurityFailure{true, reason_of(line.substr(failed + 8))};
    }
  } else if (const auto local = line.find("validating local"); local != std::string_view::npos) {
    if (const auto colon = line.find(": ", local); colon != std::string_view::npos) {
      failure = SecurityFailure{false, reason_of(line.substr(colon + 2))};
    }
  }
  const std::lock_guard lock(mutex_);
  last_ = std::string(line);
  if (failure) failure_ = std::move(failure);
}

std::optional<DdsLog::SecurityFailure> DdsLog::security_failure() const {
  const std::lock_guard lock(mutex_);
  return failure_;
}

std::string DdsLog::last_line() const {
  const std::lock_guard lock(mutex_);
  return last_;
}

std::string no_rigidd_hint(const client::BusOptions& bus, const DdsLog& log) {
  if (bus.bus == Bus::kDds && !bus.security.empty()) {
    if (const auto f = log.security_failure(); f && f->handshake) {
      return ": DDS Security authentication with a participant failed: " + f->reason +
             " (rigidd and this identity must come from one keystore, neither expired nor "
             "revoked: rigid-keys list KEYSTORE)";
    }
    return " (is rigidd running, with --security and the same --prefix and --dds-domain? If it "
           "is, it refused this identity's authentication or permissions: its log says which)";
  }
  return " (is rigidd running, with the same --transport, --prefix and --dds-domain?)";
}

std::string bus_error_line(const std::string& what, const client::BusOptions& bus,
                           const DdsLog& log) {
  if (bus.bus != Bus::kDds) return what;
  if (const auto f = log.security_failure(); f && !f->handshake && !bus.security.empty()) {
    return "DDS Security refused the identity in " + bus.security + ": " + f->reason +
           " (rigid-keys list KEYSTORE shows its dates and status)";
  }
  const std::string last = log.last_line();
  return last.empty() ? what : what + " (Cyclone DDS: " + last + ")";
}

}  // namespace rigid::clients
