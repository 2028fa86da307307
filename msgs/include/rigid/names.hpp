// The name of each value of the messages' enumerations: the one function per enumeration that
// rigidd's log, rigidctl, the view's JSON, Python's dicts and the SDK use, so that a name is spelt
// in one place. A value outside the named ones (messages carry whatever integer arrived) gets the
// fallback each function documents.
#pragma once

#include <optional>
#include <string_view>

#include "rigid/messages.hpp"

namespace rigid {

// "world", "body"; "unknown" otherwise.
constexpr std::string_view frame_name(Frame frame) {
  switch (frame) {
    case Frame::kWorld:
      return "world";
    case Frame::kBody:
      return "body";
  }
  return "unknown";
}

// The frame named "world" or "body"; nothing for any other text.
constexpr std::optional<Frame> frame_named(std::string_view name) {
  if (name == "world") return Frame::kWorld;
  if (name == "body") return Frame::kBody;
  return std::nullopt;
}

// "realtime", "fast", "lockstep"; "unknown" otherwise.
constexpr std::string_view mode_name(Mode mode) {
  switch (mode) {
    case Mode::kRealtime:
      return "realtime";
    case Mode::kFast:
      return "fast";
    case Mode::kLockstep:
      return "lockstep";
  }
  return "unknown";
}

// "pause", "resume", "step", "reset", "rate"; "none" for kNone or an unknown value.
constexpr std::string_view control_name(ControlKind kind) {
  switch (kind) {
    case ControlKind::kPause:
      return "pause";
    case ControlKind::kResume:
      return "resume";
    case ControlKind::kStep:
      return "step";
    case ControlKind::kReset:
      return "reset";
    case ControlKind::kSetRtf:
      return "rate";
    case ControlKind::kNone:
      break;
  }
  return "none";
}

// "set_state", "reset_body"; "none" for kNone or an unknown value.
constexpr std::string_view edit_name(EditKind kind) {
  switch (kind) {
    case EditKind::kSetState:
      return "set_state";
    case EditKind::kResetBody:
      return "reset_body";
    case EditKind::kNone:
      break;
  }
  return "none";
}

// "ok", "invalid", "not allowed", "failed"; "unknown outcome" otherwise.
constexpr std::string_view outcome_name(Outcome outcome) {
  switch (outcome) {
    case Outcome::kOk:
      return "ok";
    case Outcome::kInvalid:
      return "invalid";
    case Outcome::kNotAllowed:
      return "not allowed";
    case Outcome::kFailed:
      return "failed";
  }
  return "unknown outcome";
}

// "sphere", "box", "cylinder", "ellipsoid", "capsule", "plane"; "" for none (or an unknown value).
constexpr std::string_view shape_name(ShapeKind kind) {
  switch (kind) {
    case ShapeKind::kSphere:
      return "sphere";
    case ShapeKind::kBox:
      return "box";
    case ShapeKind::kCylinder:
      return "cylinder";
    case ShapeKind::kEllipsoid:
      return "ellipsoid";
    case ShapeKind::kCapsule:
      return "capsule";
    case ShapeKind::kPlane:
      return "plane";
    case ShapeKind::kNone:
      break;
  }
  return "";
}

// "impact", "resting", "sliding", "rolling", "separate"; "unknown" otherwise.
constexpr std::string_view contact_name(ContactKind kind) {
  switch (kind) {
    case ContactKind::kImpact:
      return "impact";
    case ContactKind::kResting:
      return "resting";
    case ContactKind::kSliding:
      return "sliding";
    case ContactKind::kRolling:
      return "rolling";
    case ContactKind::kSeparate:
      return "separate";
  }
  return "unknown";
}

}  // namespace rigid
