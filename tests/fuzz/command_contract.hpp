// The promises loop/command_validation.hpp makes to the loop, checked on every command a fuzzer
// makes (fuzz_lcm_messages, fuzz_dds_messages, fuzz_command_validation): a command the validator
// accepts is finite, names a body of the scene, and is within every limit (an edit's orientation
// of unit length); a refusal says why on one printable line.
#pragma once

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "fuzz_require.hpp"
#include "loop/command_validation.hpp"
#include "rigid/messages.hpp"
#include "scene/scene.hpp"

namespace rigid::fuzz {

// The server's validation, as rigidd runs it, on a small scene with tight limits (so that both
// sides of every bound are easy to reach).
class CommandContract {
 public:
  CommandContract() : bodies_(body_names()), validator_(bodies_, limits()) {}

  static std::vector<std::string> body_names() { return {"tumbler", "top", "ball", "box.1"}; }
  static scene::Limits limits() { return scene::Limits{100.0, 50.0, 5.0}; }

  void check(const rigid::WrenchCommand& w) const {
    const loop::Checked<loop::Wrench> c = validator_.check(w);
    if (!c.ok) {
      require(!c.detail.empty() && one_printable_line(c.detail), "a refusal says why on one line");
      return;
    }
    const loop::Wrench& v = c.value;
    const scene::Limits l = limits();
    require(v.body >= 0 && v.body < bodies_.size(), "an accepted wrench names a body of the scene");
    require(w.body_id >= 0 ? v.body == w.body_id : bodies_.name(v.body) == w.body_name,
            "an accepted wrench acts on the body it was sent for");
    require(finite(v.force) && finite(v.point) && finite(v.torque) && std::isfinite(v.ttl),
            "an accepted wrench is finite");
    require(known(v.force_frame) && known(v.torque_frame), "an accepted wrench has known frames");
    // Written so that NaN fails them.
    require(norm(v.force) <= l.max_force, "accepted: |force| <= max_force");
    require(norm(v.torque) <= l.max_torque, "accepted: |torque| <= max_torque");
    require(norm(cross(v.point, v.force)) <= l.max_torque,
            "accepted: |point x force| <= max_torque");
    require(v.ttl >= 0.0 && v.ttl <= l.max_ttl, "accepted: 0 <= ttl <= max_ttl");
    require(v.source == w.source && v.seq == w.seq && v.key == w.key && v.force == w.force &&
                v.point == w.point && v.torque == w.torque && v.ttl == w.ttl &&
                v.force_frame == w.force_frame && v.torque_frame == w.torque_frame &&
                v.stamp_ns == w.stamp_ns,
            "an accepted wrench reaches the loop unchanged");
  }

  void check(const rigid::ControlCommand& m) const {
    using K = rigid::ControlKind;
    loop::ReplyNote note = loop::ReplyNote::kNone;
    const loop::Checked<loop::Control> c = validator_.check(m, &note);
    if (!c.ok) {
      require(!c.detail.empty() && one_printable_line(c.detail), "a refusal says why on one line");
      require(note != loop::ReplyNote::kNone, "a refused control has a reply note");
      return;
    }
    require(note == loop::ReplyNote::kNone, "an accepted control has no reply note");
    const loop::Control& v = c.value;
    require(v.kind == K::kPause || v.kind == K::kResume || v.kind == K::kReset ||
                v.kind == K::kStep || v.kind == K::kSetRtf,
            "an accepted control is a known command");
    if (v.kind == K::kStep) {
      require(v.steps >= 1 && v.steps <= loop::CommandValidator::kMaxSteps,
              "accepted: 1 <= steps <= kMaxSteps");
    }
    if (v.kind == K::kSetRtf) {
      require(std::isfinite(v.rtf) && v.rtf > 0.0 && v.rtf <= loop::CommandValidator::kMaxRtf,
              "accepted: 0 < rtf <= kMaxRtf");
    }
    require(v.source == m.source && v.seq == m.seq && v.kind == m.command && v.steps == m.steps,
            "an accepted control reaches the loop unchanged");
  }

  void check(const rigid::EditCommand& m) const {
    using K = rigid::EditKind;
    const loop::Checked<loop::Edit> c = validator_.check(m);
    if (!c.ok) {
      require(!c.detail.empty() && one_printable_line(c.detail), "a refusal says why on one line");
      return;
    }
    const loop::Edit& v = c.value;
    require(v.kind == K::kSetState || v.kind == K::kResetBody, "an accepted edit is a known kind");
    require(v.body >= 0 && v.body < bodies_.size(), "an accepted edit names a body of the scene");
    require(m.body_id >= 0 ? v.body == m.body_id : bodies_.name(v.body) == m.body_name,
            "an accepted edit acts on the body it was sent for");
    require(v.source == m.source && v.seq == m.seq && v.kind == m.kind && v.stamp_ns == m.stamp_ns,
            "an accepted edit reaches the loop unchanged");
    if (v.kind == K::kResetBody) {
      require(v.set == 0, "an accepted reset carries no state");
      return;
    }
    require(v.set != 0 && (v.set & ~rigid::kSetAll) == 0 && v.set == m.set,
            "an accepted set_state sets known parts, as sent");
    const auto& q = v.orientation;
    const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    // Written so that NaN fails them.
    require(finite(v.position) && finite(v.linear_velocity) && finite(v.angular_velocity) &&
                std::abs(n - 1.0) <= loop::CommandValidator::kOrientationTolerance,
            "an accepted set_state is finite, its orientation a unit quaternion");
    require(known(v.velocity_frame) && known(v.angular_velocity_frame),
            "an accepted set_state has known frames");
    const auto sets = [&](std::int32_t part) { return (m.set & part) != 0; };
    require((!sets(rigid::kSetPosition) || v.position == m.position) &&
                (!sets(rigid::kSetOrientation) || v.orientation == m.orientation) &&
                (!sets(rigid::kSetLinearVelocity) || (v.linear_velocity == m.linear_velocity &&
                                                      v.velocity_frame == m.velocity_frame)) &&
                (!sets(rigid::kSetAngularVelocity) ||
                 (v.angular_velocity == m.angular_velocity &&
                  v.angular_velocity_frame == m.angular_velocity_frame)),
            "the parts an accepted set_state sets reach the loop unchanged");
  }

 private:
  using Vec3 = rigid::Vec3;
  static bool finite(const Vec3& v) {
    return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
  }
  static double norm(const Vec3& v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }
  static Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  }
  static bool known(rigid::Frame f) {
    return f == rigid::Frame::kWorld || f == rigid::Frame::kBody;
  }
  // Refusals go to rigidd's log, one event per line.
  static bool one_printable_line(const std::string& s) {
    return std::all_of(s.begin(), s.end(), [](char ch) {
      const auto u = static_cast<unsigned char>(ch);
      return u >= 0x20 && u < 0x7f;
    });
  }

  loop::BodyDirectory bodies_;
  loop::CommandValidator validator_;
};

}  // namespace rigid::fuzz
