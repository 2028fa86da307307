// Commands as the loop consumes them: validated, body names resolved to ids, fixed size and
// trivially copyable, so they travel through the bounded queue without allocating. The wire
// messages (rigid/messages.hpp) carry strings and unchecked numbers; intake.hpp turns one into
// the other.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>
#include <type_traits>
#include <variant>

#include "common/applied_command.hpp"
#include "rigid/messages.hpp"
#include "transport/decode_status.hpp"

namespace rigid::loop {

// What the loop applies (common/applied_command.hpp), named here as the loop always has.
using common::Control;
using common::Edit;
using common::Wrench;

// Why a command was refused; mirrors rigid::RejectCounts (Stats.rejected).
enum class RejectReason : std::uint8_t {
  kNonFinite,      // NaN or infinity in a number
  kUnknownBody,    // no body with that id or name
  kOverLimit,      // force, torque or ttl above the scene's limits
  kUndecodable,    // the payload did not decode
  kStaleSequence,  // sequence number not above the source's last one
  kQueueFull,      // no room: command queue or wrench table full (a flood)
  kInvalid,        // any other bad field (frame, ttl < 0, command, steps, rtf)
  kOverShare,      // the sender already holds its share of the wrench table
  kRateLimited,    // the sender is above its share of the command rate
  kNotPermitted,   // body, control or edit not permitted to the sender (security, --controls off)
};
inline constexpr int kRejectReasonCount = 10;
std::string_view to_string(RejectReason reason);

// Who sent a command, as the loop accounts for it. The key is what shares (of the wrench table,
// of the command rate) and refusal counts are kept by: with DDS Security the authenticated
// identity, otherwise the client session (a DDS writer, an LCM socket), so that a sender cannot
// pass for another by writing its source number. Fixed size: it travels in the command queue.
struct Sender {
  std::uint64_t key = 0;
  char name[80] = {};  // printable: the identity, "dds:HANDLE" or "lcm:IP:PORT"
};

struct Command {
  rigid::Bus bus = rigid::Bus::kDds;  // where it came from (a control or edit is answered there)
  std::int64_t arrival_ns = 0;        // CLOCK_MONOTONIC when the intake received it
  Sender sender;
  // Sequence numbers are kept per bus, client session and source (sequence_table.hpp), so a
  // restarted or reconnected client, or one identity's traffic, never makes another's stale.
  std::uint64_t session_key = 0;
  // One of these at a time: the queue holds 1024 commands, each the size of the largest.
  std::variant<Wrench, Control, Edit> what;
};
static_assert(std::is_trivially_copyable_v<Command>);

// Why a control request was answered as it was; the publisher turns it into the reply's text.
enum class ReplyNote : std::uint8_t {
  kNone,
  kStaleSequence,
  kUnknownCommand,
  kBadSteps,
  kBadRtf,
  kNonFinite,
  kLockstepOnlySteps,   // lockstep: only step and reset
  kRtfNeedsRealtime,    // set_rtf outside realtime mode
  kStepNeedsPause,      // step while running
  kStepInProgress,      // step while another is running
  kInterruptedByReset,  // a step cut short by reset
  kQueueFull,           // dropped: the command queue was full
  kRateLimited,         // the sender is above its share of the command rate
  kNotPermitted,        // controls are off, or the identity may not control
  kWrenchRefused,       // the answer to a refused wrench: Reply::text says why
  kEditRefused,         // an edit that failed validation: Reply::text says why
};
std::string_view to_string(ReplyNote note);

// The answer to one control request or edit, routed to the bus it came from.
struct Reply {
  rigid::Bus bus = rigid::Bus::kDds;
  std::int64_t source = 0;
  std::int64_t seq = 0;
  rigid::ControlKind kind = rigid::ControlKind::kNone;
  rigid::Outcome outcome = rigid::Outcome::kOk;
  std::int64_t tick = 0;
  ReplyNote note = ReplyNote::kNone;
  std::int64_t detail = 0;  // a number the note refers to (the last sequence, the step count)
  char text[200] = {};      // kWrenchRefused, kEditRefused: the reason, as logged
  rigid::EditKind edit = rigid::EditKind::kNone;  // kind == kReplyToEdit: what it answers
};
static_assert(std::is_trivially_copyable_v<Reply>);

// The reply's text (empty for kOk without a note).
std::string reply_message(const Reply& reply);

}  // namespace rigid::loop
