#include "loop/intake.hpp"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <string>

#include "loop/clock.hpp"

namespace rigid::loop {
namespace {

// FNV-1a: a stable 64-bit name for an identity.
std::uint64_t hash_name(std::string_view name) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (const char c : name) {
    h ^= static_cast<unsigned char>(c);
    h *= 0x100000001b3ULL;
  }
  return h;
}

// A printable copy of at most 63 characters of a name from the network.
std::string excerpt(std::string_view text) {
  std::string out;
  for (const char c : text.substr(0, 63))
    out.push_back(c >= 0x20 && c < 0x7f ? c : '?');
  return out;
}

// Room for a tenth of a second's commands, at least 50: a controller's burst passes at once.
double burst_of(double rate) {
  return std::max(50.0, rate / 10.0);
}

}  // namespace

Sender sender_of(rigid::Bus bus, const transport::Origin& origin) {
  Sender s;
  if (origin.authenticated) {
    s.key = hash_name(origin.identity);
    const std::size_t n = std::min(origin.identity.size(), sizeof s.name - 1);
    std::memcpy(s.name, origin.identity.data(), n);
    for (std::size_t i = 0; i < n; ++i)
      if (s.name[i] < 0x20 || s.name[i] >= 0x7f) s.name[i] = '?';
    return s;
  }
  s.key = util::mix64(origin.session ^ (bus == rigid::Bus::kDds ? 0x5ddULL << 48 : 0x1c3ULL << 48));
  if (bus == rigid::Bus::kDds) {
    std::snprintf(s.name, sizeof s.name, "dds:%016llx",
                  static_cast<unsigned long long>(origin.session));
  } else {
    const auto address = static_cast<std::uint32_t>(origin.session >> 16);
    std::snprintf(s.name, sizeof s.name, "lcm:%u.%u.%u.%u:%u", (address >> 24) & 0xffU,
                  (address >> 16) & 0xffU, (address >> 8) & 0xffU, address & 0xffU,
                  static_cast<unsigned>(origin.session & 0xffffU));
  }
  return s;
}

std::uint64_t owner_of(const transport::Origin& origin) {
  return origin.authenticated ? hash_name(origin.identity) : 0;
}

// The key a command's session is known by: the writer's session and owner, apart per bus.
std::uint64_t session_key(rigid::Bus bus, const transport::Origin& origin) {
  return util::mix64(origin.session ^ owner_of(origin) ^
                     (bus == rigid::Bus::kDds ? 0x5ddULL << 48 : 0x1c3ULL << 48));
}

Intake::Intake(rigid::Bus bus, const CommandValidator& validator, const IntakePolicy& policy,
               BoundedQueue<Command>& queue, Doorbell& doorbell, RejectCounters& rejects,
               ReplySink& replies)
    : bus_(bus),
      validator_(validator),
      policy_(policy),
      queue_(queue),
      doorbell_(doorbell),
      rejects_(rejects),
      replies_(replies),
      rates_(policy.commands_per_second, burst_of(policy.commands_per_second), 1024) {}

bool Intake::enqueue(Command& command) {
  command.arrival_ns = monotonic_ns();
  if (!queue_.try_push(command)) return false;
  doorbell_.ring();
  return true;
}

void answer_refused_wrench(ReplySink& replies, RejectCounters& rejects, rigid::Bus bus,
                           std::int64_t source, std::int64_t seq, const Sender& sender,
                           std::string_view why, std::int64_t tick) {
  if (!rejects.reply_allowed(sender, monotonic_ns())) return;
  Reply reply{bus,
              source,
              seq,
              rigid::kReplyToWrench,
              rigid::Outcome::kInvalid,
              tick,
              ReplyNote::kWrenchRefused,
              0};
  const std::size_t n = std::min(why.size(), sizeof reply.text - 1);
  std::memcpy(reply.text, why.data(), n);
  reply.text[n] = '\0';
  replies.reply(reply);
}

void Intake::refuse_wrench(const rigid::WrenchCommand& wrench, const Sender& sender,
                           RejectReason reason, const std::string& detail) {
  rejects_.record(reason, detail, &sender);
  answer_refused_wrench(replies_, rejects_, bus_, wrench.source, wrench.seq, sender,
                        std::string(to_string(reason)) + ": " + detail, 0);
}

void Intake::on_wrench(const rigid::WrenchCommand& wrench, const transport::Origin& origin) {
  const Sender sender = sender_of(bus_, origin);
  const auto who = [&] {
    return "wrench from " + std::string(sender.name) + " source " + std::to_string(wrench.source) +
           " seq " + std::to_string(wrench.seq) + ": ";
  };
  if (policy_.secure && !origin.authenticated) {
    refuse_wrench(wrench, sender, RejectReason::kNotPermitted,
                  who() + "not from an authenticated writer in a push/IDENTITY/BODY partition");
    return;
  }
  if (!rates_.take(sender.key, monotonic_ns())) {
    refuse_wrench(wrench, sender, RejectReason::kRateLimited,
                  who() + "above the sender's share of the command rate (" +
                      std::to_string(static_cast<long long>(policy_.commands_per_second)) +
                      " per second)");
    return;
  }
  Checked<Wrench> checked = validator_.check(wrench);
  if (!checked.ok) {
    refuse_wrench(wrench, sender, checked.reason, checked.detail);
    return;
  }
  if (policy_.secure && validator_.bodies().name(checked.value.body) != origin.permitted_body) {
    refuse_wrench(wrench, sender, RejectReason::kNotPermitted,
                  who() + "body '" + excerpt(validator_.bodies().name(checked.value.body)) +
                      "' is not the one its writer's partition permits ('" +
                      excerpt(origin.permitted_body) + "')");
    return;
  }
  Command command;
  command.bus = bus_;
  command.sender = sender;
  checked.value.owner = owner_of(origin);
  command.session_key = session_key(bus_, origin);
  command.what = checked.value;
  if (!enqueue(command)) {
    char detail[200];
    std::snprintf(detail, sizeof detail,
                  "command queue full (%zu): wrench from %s seq %lld dropped", queue_.capacity(),
                  sender.name, static_cast<long long>(wrench.seq));
    refuse_wrench(wrench, sender, RejectReason::kQueueFull, detail);
  }
}

// A control or an edit: allowed only with controls on and, with security, from an authenticated
// control/IDENTITY writer; then within the sender's share of the command rate. A refusal is
// counted and answered (at most at the sender's reply rate).
bool Intake::admit_privileged(const Sender& sender, const transport::Origin& origin,
                              std::string_view what, std::int64_t source, std::int64_t seq,
                              Reply& reply) {
  const auto who = [&] {
    return std::string(what) + " from " + std::string(sender.name) + " source " +
           std::to_string(source) + " seq " + std::to_string(seq) + ": ";
  };
  RejectReason reason;
  std::string detail;
  if (!policy_.controls || (policy_.secure && !origin.authenticated)) {
    reason = RejectReason::kNotPermitted;
    detail = who() + (policy_.controls ? "not from an authenticated control/IDENTITY writer"
                                       : "controls are off (rigidd --controls off)");
    reply.note = ReplyNote::kNotPermitted;
  } else if (!rates_.take(sender.key, monotonic_ns())) {
    reason = RejectReason::kRateLimited;
    detail = who() + "above the sender's share of the command rate";
    reply.note = ReplyNote::kRateLimited;
  } else {
    return true;
  }
  rejects_.record(reason, detail, &sender);
  reply.outcome = rigid::Outcome::kNotAllowed;
  if (rejects_.reply_allowed(sender, monotonic_ns())) replies_.reply(reply);
  return false;
}

void Intake::on_control(const rigid::ControlCommand& control, const transport::Origin& origin) {
  const Sender sender = sender_of(bus_, origin);
  Reply reply{bus_,
              control.source,
              control.seq,
              control.command,
              rigid::Outcome::kInvalid,
              0,
              ReplyNote::kNone,
              0};
  if (!admit_privileged(sender, origin, "control", control.source, control.seq, reply)) return;
  ReplyNote note = ReplyNote::kNone;
  Checked<Control> checked = validator_.check(control, &note);
  reply.note = note;
  if (!checked.ok) {
    rejects_.record(checked.reason, checked.detail, &sender);
    replies_.reply(reply);
    return;
  }
  Command command;
  command.bus = bus_;
  command.sender = sender;
  command.session_key = session_key(bus_, origin);
  command.what = checked.value;
  if (!enqueue(command)) {
    rejects_.recordf(RejectReason::kQueueFull, &sender,
                     "command queue full (%zu): control from %s seq %lld dropped",
                     queue_.capacity(), sender.name, static_cast<long long>(control.seq));
    reply.outcome = rigid::Outcome::kFailed;
    reply.note = ReplyNote::kQueueFull;
    replies_.reply(reply);
  }
}

void Intake::on_decode_error(const transport::DecodeError& error) {
  rejects_.recordf(RejectReason::kUndecodable, nullptr, "%.*s payload on %.*s (%zu bytes): %.*s",
                   static_cast<int>(to_string(error.bus).size()), to_string(error.bus).data(),
                   static_cast<int>(to_string(error.topic).size()), to_string(error.topic).data(),
                   error.payload_size, static_cast<int>(to_string(error.status).size()),
                   to_string(error.status).data());
}

void Intake::on_edit(const rigid::EditCommand& edit, const transport::Origin& origin) {
  const Sender sender = sender_of(bus_, origin);
  Reply reply{bus_, edit.source,      edit.seq, rigid::kReplyToEdit, rigid::Outcome::kInvalid,
              0,    ReplyNote::kNone, 0};
  reply.edit = edit.kind;
  // Edits are allowed where controls are: the same switch and, with security, the same
  // control/IDENTITY partition.
  if (!admit_privileged(sender, origin, "edit", edit.source, edit.seq, reply)) return;
  const Checked<Edit> checked = validator_.check(edit);
  if (!checked.ok) {
    rejects_.record(checked.reason, checked.detail, &sender);
    reply.note = ReplyNote::kEditRefused;
    const std::string why = std::string(to_string(checked.reason)) + ": " + checked.detail;
    const std::size_t n = std::min(why.size(), sizeof reply.text - 1);
    std::memcpy(reply.text, why.data(), n);
    reply.text[n] = '\0';
    replies_.reply(reply);
    return;
  }
  Command command;
  command.bus = bus_;
  command.sender = sender;
  command.session_key = session_key(bus_, origin);
  command.what = checked.value;
  if (!enqueue(command)) {
    rejects_.recordf(RejectReason::kQueueFull, &sender,
                     "command queue full (%zu): edit from %s seq %lld dropped", queue_.capacity(),
                     sender.name, static_cast<long long>(edit.seq));
    reply.outcome = rigid::Outcome::kFailed;
    reply.note = ReplyNote::kQueueFull;
    replies_.reply(reply);
  }
}

}  // namespace rigid::loop
