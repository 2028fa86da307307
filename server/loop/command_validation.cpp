#include "loop/command_validation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>

namespace rigid::loop {
namespace {

bool finite(const Vec3& v) {
  return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

double norm(const Vec3& v) {
  return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

std::string num(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.9g", v);
  return buffer;
}

std::string vec(const Vec3& v) {
  return "(" + num(v[0]) + ", " + num(v[1]) + ", " + num(v[2]) + ")";
}

bool known_frame(rigid::Frame f) {
  return f == rigid::Frame::kWorld || f == rigid::Frame::kBody;
}

// A bounded, printable excerpt of a name from the network.
std::string shown_name(const std::string& name) {
  std::string shown;
  for (char c : name.substr(0, 64))
    shown += (c >= 0x20 && c < 0x7f) ? c : '?';
  return shown;
}

template <class T>
Checked<T> refuse(RejectReason reason, std::string detail) {
  Checked<T> c;
  c.reason = reason;
  c.detail = std::move(detail);
  return c;
}

}  // namespace

BodyDirectory::BodyDirectory(std::vector<std::string> names) : names_(std::move(names)) {
  by_name_.resize(names_.size());
  std::iota(by_name_.begin(), by_name_.end(), 0);
  // Ties (the world refuses duplicate names) go to the lower id, as (name, id) pairs sorted.
  std::sort(by_name_.begin(), by_name_.end(), [this](std::int32_t a, std::int32_t b) {
    const int c = names_[static_cast<std::size_t>(a)].compare(names_[static_cast<std::size_t>(b)]);
    return c < 0 || (c == 0 && a < b);
  });
}

int BodyDirectory::find(std::string_view name) const {
  const auto it = std::lower_bound(
      by_name_.begin(), by_name_.end(), name,
      [this](std::int32_t id, std::string_view n) { return std::string_view(this->name(id)) < n; });
  return it != by_name_.end() && this->name(*it) == name ? *it : -1;
}

Checked<Wrench> CommandValidator::check(const rigid::WrenchCommand& w) const {
  using R = RejectReason;
  // Built only for a refusal: a valid command (the common case) allocates nothing here.
  const auto who = [&w] {
    return "wrench from source " + std::to_string(w.source) + " seq " + std::to_string(w.seq) +
           ": ";
  };
  if (!finite(w.force)) return refuse<Wrench>(R::kNonFinite, who() + "force " + vec(w.force));
  if (!finite(w.point)) return refuse<Wrench>(R::kNonFinite, who() + "point " + vec(w.point));
  if (!finite(w.torque)) return refuse<Wrench>(R::kNonFinite, who() + "torque " + vec(w.torque));
  if (!std::isfinite(w.ttl)) return refuse<Wrench>(R::kNonFinite, who() + "ttl " + num(w.ttl));

  int body = -1;
  if (w.body_id >= 0) {
    if (w.body_id >= bodies_.size()) {
      return refuse<Wrench>(R::kUnknownBody, who() + "body_id " + std::to_string(w.body_id) +
                                                 " (the scene has " +
                                                 std::to_string(bodies_.size()) + " bodies)");
    }
    body = w.body_id;
  } else {
    body = bodies_.find(w.body_name);
    if (body < 0) {
      return refuse<Wrench>(R::kUnknownBody, who() + "body_name '" + shown_name(w.body_name) + "'");
    }
  }

  if (!known_frame(w.force_frame)) {
    return refuse<Wrench>(R::kInvalid,
                          who() + "force_frame " + std::to_string(static_cast<int>(w.force_frame)));
  }
  if (!known_frame(w.torque_frame)) {
    return refuse<Wrench>(
        R::kInvalid, who() + "torque_frame " + std::to_string(static_cast<int>(w.torque_frame)));
  }
  if (w.ttl < 0.0) return refuse<Wrench>(R::kInvalid, who() + "ttl " + num(w.ttl) + " < 0");

  const double force = norm(w.force);
  if (force > limits_.max_force) {
    return refuse<Wrench>(R::kOverLimit, who() + "|force| " + num(force) + " N > max_force " +
                                             num(limits_.max_force));
  }
  const double torque = norm(w.torque);
  if (torque > limits_.max_torque) {
    return refuse<Wrench>(R::kOverLimit, who() + "|torque| " + num(torque) + " N m > max_torque " +
                                             num(limits_.max_torque));
  }
  // A modest force at a huge lever arm is a huge torque: bound its moment too. Written to refuse
  // NaN: with a lever arm near 1e308 the cross product is inf - inf (found by fuzzing).
  const double moment = norm(cross(w.point, w.force));
  if (!(moment <= limits_.max_torque)) {
    return refuse<Wrench>(R::kOverLimit, who() + "|point x force| " + num(moment) +
                                             " N m > max_torque " + num(limits_.max_torque));
  }
  if (w.ttl > limits_.max_ttl) {
    return refuse<Wrench>(R::kOverLimit,
                          who() + "ttl " + num(w.ttl) + " s > max_ttl " + num(limits_.max_ttl));
  }

  Checked<Wrench> c;
  c.ok = true;
  c.value.wrench() = w.wrench();
  c.value.source = w.source;
  c.value.seq = w.seq;
  c.value.key = w.key;
  c.value.body = body;
  c.value.stamp_ns = w.stamp_ns;
  return c;
}

Checked<Control> CommandValidator::check(const rigid::ControlCommand& m, ReplyNote* note) const {
  using K = rigid::ControlKind;
  using R = RejectReason;
  const auto who = [&m] {
    return "control from source " + std::to_string(m.source) + " seq " + std::to_string(m.seq) +
           ": ";
  };
  *note = ReplyNote::kNone;
  switch (m.command) {
    case K::kPause:
    case K::kResume:
    case K::kReset:
      break;
    case K::kStep:
      if (m.steps < 1 || m.steps > kMaxSteps) {
        *note = ReplyNote::kBadSteps;
        return refuse<Control>(R::kInvalid, who() + "steps " + std::to_string(m.steps) +
                                                " (expected 1 .. " + std::to_string(kMaxSteps) +
                                                ")");
      }
      break;
    case K::kSetRtf:
      if (!std::isfinite(m.rtf)) {
        *note = ReplyNote::kNonFinite;
        return refuse<Control>(R::kNonFinite, who() + "rtf " + num(m.rtf));
      }
      if (!(m.rtf > 0.0) || m.rtf > kMaxRtf) {
        *note = ReplyNote::kBadRtf;
        return refuse<Control>(R::kInvalid,
                               who() + "rtf " + num(m.rtf) + " (expected > 0 and <= 1000)");
      }
      break;
    default:
      *note = ReplyNote::kUnknownCommand;
      return refuse<Control>(R::kInvalid,
                             who() + "command " + std::to_string(static_cast<int>(m.command)));
  }
  Checked<Control> c;
  c.ok = true;
  c.value = Control{m.source, m.seq, m.command, m.steps, m.rtf};
  return c;
}

Checked<Edit> CommandValidator::check(const rigid::EditCommand& m) const {
  using K = rigid::EditKind;
  using R = RejectReason;
  const auto who = [&m] {
    return "edit from source " + std::to_string(m.source) + " seq " + std::to_string(m.seq) + ": ";
  };
  if (m.kind != K::kSetState && m.kind != K::kResetBody) {
    return refuse<Edit>(R::kInvalid, who() + "kind " + std::to_string(static_cast<int>(m.kind)) +
                                         " (expected 1 set_state or 2 reset_body)");
  }
  const bool sets_state = m.kind == K::kSetState;
  const auto sets = [&](std::int32_t part) { return sets_state && (m.set & part) != 0; };
  // Only the parts the edit sets are looked at: the others are never applied.
  if (sets(rigid::kSetPosition) && !finite(m.position)) {
    return refuse<Edit>(R::kNonFinite, who() + "position " + vec(m.position));
  }
  const auto& q = m.orientation;
  if (sets(rigid::kSetOrientation) &&
      !(std::isfinite(q[0]) && std::isfinite(q[1]) && std::isfinite(q[2]) && std::isfinite(q[3]))) {
    return refuse<Edit>(R::kNonFinite, who() + "orientation (" + num(q[0]) + ", " + num(q[1]) +
                                           ", " + num(q[2]) + ", " + num(q[3]) + ")");
  }
  if (sets(rigid::kSetLinearVelocity) && !finite(m.linear_velocity)) {
    return refuse<Edit>(R::kNonFinite, who() + "linear_velocity " + vec(m.linear_velocity));
  }
  if (sets(rigid::kSetAngularVelocity) && !finite(m.angular_velocity)) {
    return refuse<Edit>(R::kNonFinite, who() + "angular_velocity " + vec(m.angular_velocity));
  }

  int body = -1;
  if (m.body_id >= 0) {
    if (m.body_id >= bodies_.size()) {
      return refuse<Edit>(R::kUnknownBody, who() + "body_id " + std::to_string(m.body_id) +
                                               " (the scene has " + std::to_string(bodies_.size()) +
                                               " bodies)");
    }
    body = m.body_id;
  } else {
    body = bodies_.find(m.body_name);
    if (body < 0) {
      return refuse<Edit>(R::kUnknownBody, who() + "body_name '" + shown_name(m.body_name) + "'");
    }
  }

  if (sets_state) {
    if (m.set == 0 || (m.set & ~rigid::kSetAll) != 0) {
      return refuse<Edit>(R::kInvalid, who() + "set " + std::to_string(m.set) +
                                           " (expected a combination of 1 position, 2 "
                                           "orientation, 4 linear_velocity, 8 angular_velocity)");
    }
    if (sets(rigid::kSetLinearVelocity) && !known_frame(m.velocity_frame)) {
      return refuse<Edit>(R::kInvalid, who() + "velocity_frame " +
                                           std::to_string(static_cast<int>(m.velocity_frame)));
    }
    if (sets(rigid::kSetAngularVelocity) && !known_frame(m.angular_velocity_frame)) {
      return refuse<Edit>(R::kInvalid,
                          who() + "angular_velocity_frame " +
                              std::to_string(static_cast<int>(m.angular_velocity_frame)));
    }
    if (sets(rigid::kSetOrientation)) {
      const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
      if (!(std::abs(n - 1.0) <= kOrientationTolerance)) {
        return refuse<Edit>(R::kInvalid, who() + "orientation (" + num(q[0]) + ", " + num(q[1]) +
                                             ", " + num(q[2]) + ", " + num(q[3]) + "): |q| " +
                                             num(n) + " is not 1 (within 1e-3)");
      }
    }
  }

  Checked<Edit> c;
  c.ok = true;
  c.value.source = m.source;
  c.value.seq = m.seq;
  c.value.kind = m.kind;
  c.value.body = body;
  c.value.stamp_ns = m.stamp_ns;
  if (sets_state) {
    // Only what is set travels on: the journal and rigid/accepted carry the edit as applied.
    c.value.set = m.set;
    if (sets(rigid::kSetPosition)) c.value.position = m.position;
    if (sets(rigid::kSetOrientation)) c.value.orientation = m.orientation;
    if (sets(rigid::kSetLinearVelocity)) {
      c.value.linear_velocity = m.linear_velocity;
      c.value.velocity_frame = m.velocity_frame;
    }
    if (sets(rigid::kSetAngularVelocity)) {
      c.value.angular_velocity = m.angular_velocity;
      c.value.angular_velocity_frame = m.angular_velocity_frame;
    }
  }
  return c;
}

}  // namespace rigid::loop
