// The checks a command from the network must pass before it may reach the loop, that depend only
// on the scene (immutable once running), so transport threads can run them concurrently:
// finite numbers, a known body (by id or by name), force, torque and time to live within the
// scene's limits, known enumerations, a unit orientation. Per-source sequence numbers need state
// and are checked by the loop (sequence_table.hpp).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "loop/command.hpp"
#include "rigid/messages.hpp"
#include "scene/scene.hpp"

namespace rigid::loop {

// The scene's body ids (0 .. n-1, the physics ids) and names, for lookups that allocate nothing.
class BodyDirectory {
 public:
  explicit BodyDirectory(std::vector<std::string> names);
  int size() const { return static_cast<int>(names_.size()); }
  // -1 if there is no such body.
  int find(std::string_view name) const;
  const std::string& name(int id) const { return names_[static_cast<std::size_t>(id)]; }

 private:
  std::vector<std::string> names_;
  // The ids in the order of their names: 4 B a body, where (name, id) pairs held every name twice.
  std::vector<std::int32_t> by_name_;
};

template <class T>
struct Checked {
  bool ok = false;
  T value{};                                     // when ok
  RejectReason reason = RejectReason::kInvalid;  // when !ok
  std::string detail;                            // when !ok: one line naming the field and value
};

class CommandValidator {
 public:
  CommandValidator(const BodyDirectory& bodies, const scene::Limits& limits)
      : bodies_(bodies), limits_(limits) {}

  // Checks, in order: finite numbers, known body, frames, limits (|force| <= max_force;
  // |torque| and the moment |point x force| <= max_torque; 0 <= ttl <= max_ttl).
  Checked<Wrench> check(const rigid::WrenchCommand& wrench) const;
  // Checks the command is known and its argument well-formed (step: steps >= 1; set_rtf: finite,
  // 0 < rtf <= kMaxRtf). A refused control carries the reply note in `note`.
  Checked<Control> check(const rigid::ControlCommand& control, ReplyNote* note) const;
  // Checks, in order: a known kind; finite numbers; a known body; for kSetState, at least one
  // part set and no unknown bit, known frames, and an orientation (when set) within
  // kOrientationTolerance of unit length.
  Checked<Edit> check(const rigid::EditCommand& edit) const;

  const BodyDirectory& bodies() const { return bodies_; }
  const scene::Limits& limits() const { return limits_; }

  static constexpr double kMaxRtf = 1000.0;
  // | |q| - 1 | at most: a quaternion typed with four decimals passes, a wrong one does not.
  static constexpr double kOrientationTolerance = 1e-3;
  static constexpr std::int64_t kMaxSteps = 1'000'000'000;

 private:
  const BodyDirectory& bodies_;
  scene::Limits limits_;
};

}  // namespace rigid::loop
