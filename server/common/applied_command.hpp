// Commands as the loop applies them: validated, body names resolved to ids, fixed size and
// trivially copyable. The loop's intake makes them (loop/command_validation.hpp), the wrench table
// holds the wrenches, the journal records them all and a replay applies them again.
#pragma once

#include <cstdint>
#include <type_traits>

#include "rigid/messages.hpp"

namespace rigid::common {

// A wrench (rigid::Wrench: force, point, frames, torque, ttl in s of simulated time) that passed
// validation, on a body that is a valid id; its numbers are finite and within limits.
struct Wrench : rigid::Wrench {
  // With DDS Security, the identity that wrote it (a hash; 0 without): part of the key of the
  // wrench table, so that no identity can replace another's wrenches.
  std::uint64_t owner = 0;
  std::int64_t source = 0;
  std::int64_t seq = 0;
  std::int32_t key = 0;
  std::int32_t body = 0;
  std::int64_t stamp_ns = 0;  // the sender's stamp (CLOCK_REALTIME), passed through
};

// A control request whose fields are well-formed (known command, steps > 0, finite rtf > 0).
// Whether it is allowed now is the loop's decision.
struct Control {
  std::int64_t source = 0;
  std::int64_t seq = 0;
  rigid::ControlKind kind = rigid::ControlKind::kNone;
  std::int64_t steps = 0;
  double rtf = 0.0;
};

// An edit whose numbers are finite and fields known (a kind, frames, a non-zero orientation when it
// sets one), on a body that is a valid id. The loop makes it between two ticks
// (DrivenWorld::edit).
struct Edit : rigid::StateEdit {
  std::int64_t source = 0;
  std::int64_t seq = 0;
  rigid::EditKind kind = rigid::EditKind::kNone;
  std::int32_t body = 0;
  std::int64_t stamp_ns = 0;  // the sender's stamp (CLOCK_REALTIME), passed through
};

static_assert(std::is_trivially_copyable_v<Wrench>);
static_assert(std::is_trivially_copyable_v<Control>);
static_assert(std::is_trivially_copyable_v<Edit>);

}  // namespace rigid::common
