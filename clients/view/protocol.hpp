// What rigid-view and its page say to each other over the WebSocket, as pure functions (no I/O):
// the binary state frame, the JSON texts (scene, stats, answers) and the page's commands, checked.
//
// State frame (binary, little-endian, 8-byte aligned so that the page reads it as typed arrays):
//   u32 magic kStateMagic, u32 n (bodies), u32 scene generation, u32 0, i64 tick, f64 sim_time,
//   f64 position[3n] (p_WBo), f64 orientation[4n] (q_WB as w, x, y, z), i32 id[n].
// Page commands (text, at most kMaxCommandBytes, one flat JSON object):
//   {"op":"pause"|"resume"|"reset","id":N}   {"op":"step","id":N,"steps":K}
//   {"op":"push","body":ID,"force":[x,y,z],"point":[x,y,z]}   (force in W, point from the CoM in B)
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>

#include "rigid/messages.hpp"

namespace rigid::view {

inline constexpr std::uint32_t kStateMagic = 0x31565752;  // "RWV1" in the frame's first bytes
inline constexpr std::size_t kStateHeaderBytes = 32;
inline constexpr std::size_t kMaxCommandBytes = 512;
inline constexpr std::int64_t kMaxSteps = 1'000'000;
inline constexpr std::int64_t kMaxCommandId = (std::int64_t{1} << 53);  // exact in JavaScript
inline constexpr double kMaxPushForce = 1e4;  // N; rigidd's limits.max_force still applies
inline constexpr double kMaxPushPoint = 100;  // m from the centre of mass

// The state as the page reads it.
std::string encode_state(const StateFrame& state, std::uint32_t scene_generation);

// {"type":"scene", ...}: each body's id, name and what to draw: "box" (size), "sphere",
// "cylinder", "capsule", "ellipsoid" (dims as in SceneDescription), or for a body without a shape
// the uniform box with its principal moments ("box", size, and "frame": the principal axes in B
// as w, x, y, z).
std::string scene_json(const SceneDescription& scene, std::uint64_t generation);
std::string stats_json(const StatsReport& stats);
// {"type":"hello","read_only":B,"source":N}
std::string hello_json(bool read_only, std::uint64_t connection);
// {"type":"reply","id":N,"op":"pause","ok":B,"outcome":"ok","tick":T,"message":"..."}
std::string reply_json(std::int64_t id, std::string_view op, bool ok, std::string_view outcome,
                       std::int64_t tick, std::string_view message);
// {"type":"error","message":"..."}: a refused frame.
std::string error_json(std::string_view message);

enum class Op { kPause, kResume, kStep, kReset, kPush };
std::string_view op_name(Op op);

struct PageCommand {
  Op op = Op::kPause;
  std::int64_t id = 0;
  std::int64_t steps = 0;  // kStep
  std::int32_t body = -1;  // kPush
  rigid::Vec3 force{};     // kPush
  rigid::Vec3 point{};     // kPush
  bool operator==(const PageCommand&) const = default;
};

// The command, or one line saying why the text is refused.
std::variant<PageCommand, std::string> parse_command(std::string_view text);

// The uniform box with the same principal moments as `inertia` (Ixx, Iyy, Izz, Ixy, Ixz, Iyz) and
// `mass`: its edge lengths and the principal axes in B (w, x, y, z). Exposed for the tests.
struct MomentBox {
  rigid::Vec3 size{};
  std::array<double, 4> frame{1, 0, 0, 0};
};
MomentBox box_of_moments(double mass, const double* inertia);

}  // namespace rigid::view
