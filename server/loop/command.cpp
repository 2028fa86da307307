#include "loop/command.hpp"

#include <cstring>
#include <string>

namespace rigid::loop {

std::string_view to_string(RejectReason reason) {
  switch (reason) {
    case RejectReason::kNonFinite:
      return "non_finite";
    case RejectReason::kUnknownBody:
      return "unknown_body";
    case RejectReason::kOverLimit:
      return "over_limit";
    case RejectReason::kUndecodable:
      return "undecodable";
    case RejectReason::kStaleSequence:
      return "stale_sequence";
    case RejectReason::kQueueFull:
      return "queue_full";
    case RejectReason::kInvalid:
      return "invalid";
    case RejectReason::kOverShare:
      return "over_share";
    case RejectReason::kRateLimited:
      return "rate_limited";
    case RejectReason::kNotPermitted:
      return "not_permitted";
  }
  return "unknown";
}

std::string_view to_string(ReplyNote note) {
  switch (note) {
    case ReplyNote::kNone:
      return "";
    case ReplyNote::kStaleSequence:
      return "stale sequence number";
    case ReplyNote::kUnknownCommand:
      return "unknown command";
    case ReplyNote::kBadSteps:
      return "steps must be >= 1 and <= 1000000000";  // CommandValidator::kMaxSteps
    case ReplyNote::kBadRtf:
      return "rtf must be > 0 and <= 1000";
    case ReplyNote::kNonFinite:
      return "rtf is not a finite number";
    case ReplyNote::kLockstepOnlySteps:
      return "lockstep mode advances only on step requests (step and reset are allowed)";
    case ReplyNote::kRtfNeedsRealtime:
      return "the real-time factor applies to realtime mode only";
    case ReplyNote::kStepNeedsPause:
      return "step needs the loop paused (send pause first)";
    case ReplyNote::kStepInProgress:
      return "a step request is still running";
    case ReplyNote::kInterruptedByReset:
      return "interrupted by reset";
    case ReplyNote::kQueueFull:
      return "dropped: the command queue is full";
    case ReplyNote::kRateLimited:
      return "refused: this sender is above its share of the command rate "
             "(limits.max_commands_per_second)";
    case ReplyNote::kNotPermitted:
      return "not permitted: rigidd runs with --controls off, or this identity may not control "
             "(controls and edits)";
    case ReplyNote::kWrenchRefused:
    case ReplyNote::kEditRefused:
      return "refused";
  }
  return "";
}

std::string reply_message(const Reply& reply) {
  std::string text(to_string(reply.note));
  switch (reply.note) {
    case ReplyNote::kStaleSequence:
      text += " (the source's last one is " + std::to_string(reply.detail) + ")";
      break;
    case ReplyNote::kStepInProgress:
      text += " (" + std::to_string(reply.detail) + " ticks left)";
      break;
    case ReplyNote::kInterruptedByReset:
      text += " after " + std::to_string(reply.detail) + " ticks";
      break;
    case ReplyNote::kWrenchRefused:
    case ReplyNote::kEditRefused:
      text = std::string(reply.text, strnlen(reply.text, sizeof reply.text));
      break;
    default:
      break;
  }
  return text;
}

}  // namespace rigid::loop
