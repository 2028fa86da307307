// What rigid-view and its page say to each other over the WebSocket, as pure functions (no I/O):
// the binary state frame, the JSON texts (scene, stats, answers) and the page's commands, checked.
//
// State frame (binary, little-endian, each array aligned to its type so that the page reads it
// as typed arrays):
//   u32 magic kStateMagic, u32 n (bodies), u32 scene generation, u32 flags, i64 tick, f64
//   sim_time, i64 stamp_ns (rigidd's wall clock at publish: the page's latency), real
//   position[3n] (p_WBo), real orientation[4n] (q_WB as w, x, y, z), real linear_velocity[3n]
//   (v_WBo in W), real angular_velocity[3n] (w_WB in W, as rigidd publishes it: msgs/rigid.idl),
//   f32 energy_drift[n], f32 momentum_drift[n] (relative, since each body's reference: drift.hpp),
//   i32 id[n]. real is f64, the published doubles, for scenes of up to kExactStateMaxBodies
//   bodies, and f32 (flag kStateFloat32) for larger recordings (rigid-view FILE, whose frames
//   are made once at load for every page): what the page's GPU draws anyway, and the bytes are
//   what a large scene's state costs on the way (bench/notes/view-bench.md). Total
//   kStateHeaderBytes + state_bytes_per_body(n) n.
// Pose frame (live scenes of more than kExactStateMaxBodies bodies: flag kStatePoses): the same
//   header, then f32 position[3n], f32 orientation[4n], i32 id[n] (32 B a body, half the state
//   frame's: a 10^4-body page draws what it receives, bench/notes/view-bench.md), the worst drifts
//   (f32 energy, i32 its slot, f32 momentum, i32 its slot; slot -1 when every drift is 0), u32 k,
//   u32 0, and k watched bodies' records of kWatchedRecordBytes: i32 slot, f32 energy drift, f32
//   momentum drift, u32 0, f64 position[3], orientation[4], linear_velocity[3],
//   angular_velocity[3] (the published doubles). The watched bodies are those the pages asked
//   for ({"op":"watch"}): the body panel shows them exactly, velocities included.
// Page commands (text, at most kMaxCommandBytes, one flat JSON object):
//   {"op":"pause"|"resume"|"reset","id":N}   {"op":"step","id":N,"steps":K}
//   {"op":"push","body":ID,"force":[x,y,z],"point":[x,y,z]}   (force in W, point from the CoM in B)
//   {"op":"set_state","id":N,"body":ID, and one or more of "position":[x,y,z] (p_WBo),
//    "orientation":[w,x,y,z] (q_WB), "velocity":[x,y,z], "angular_velocity":[x,y,z] (in W)}
//   {"op":"reset_body","id":N,"body":ID}   (rigidd's edits, answered like the controls)
//   {"op":"ack"}   (exactly these bytes: the page has drawn a state frame; see kAckCommand)
//   {"op":"watch","body":ID} or {"op":"watch"} (none): the body whose exact state this page shows
//   (pose frames' watched records); re-sent every second while it holds (kWatchLifetime), no
//   answer, allowed with --read-only and in playback (whose frames are whole: ignored there).
// Playback (rigid-view FILE, hello's "mode":"playback"): pause as above, and
//   {"op":"play","id":N}   {"op":"seek","id":N,"tick":T} or {...,"time":S}
//   {"op":"speed","id":N,"speed":X}
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "rigid/messages.hpp"

namespace rigid::view {

// The frames' layout (see the top). The page decodes frames with these very numbers:
// page_constants.cpp writes them into its protocol_constants.js when rigid-view is built.
inline constexpr std::uint32_t kStateMagic = 0x33565752;  // "RWV3" (with drifts, f32 or f64)
inline constexpr std::size_t kStateHeaderBytes = 40;
// The header's fields, in bytes from the frame's start (the magic is at 0).
inline constexpr std::size_t kStateBodiesAt = 4;
inline constexpr std::size_t kStateGenerationAt = 8;
inline constexpr std::size_t kStateFlagsAt = 12;
inline constexpr std::size_t kStateTickAt = 16;
inline constexpr std::size_t kStateSimTimeAt = 24;
inline constexpr std::size_t kStateStampAt = 32;
inline constexpr std::uint32_t kStateFloat32 = 1;  // flags: the per-body reals are f32
inline constexpr std::uint32_t kStatePoses = 2;    // flags: a pose frame (see the top)
inline constexpr std::size_t kExactStateMaxBodies = 256;
// A pose frame: its per-body arrays' bytes a body, then its trailer (the worst drifts and the
// count of watched records, in bytes from the trailer's start), then the watched records (each
// field in bytes from the record's start; the slot is at 0).
inline constexpr std::size_t kPoseBytesPerBody = 32;
inline constexpr std::size_t kPoseTrailerBytes = 24;
inline constexpr std::size_t kPoseWorstEnergyAt = 0;
inline constexpr std::size_t kPoseWorstEnergySlotAt = 4;
inline constexpr std::size_t kPoseWorstMomentumAt = 8;
inline constexpr std::size_t kPoseWorstMomentumSlotAt = 12;
inline constexpr std::size_t kPoseWatchedCountAt = 16;
inline constexpr std::size_t kWatchedRecordBytes = 120;
inline constexpr std::size_t kWatchedEnergyAt = 4;
inline constexpr std::size_t kWatchedMomentumAt = 8;
inline constexpr std::size_t kWatchedStateAt = 16;  // f64 position, orientation, velocities: 13
inline constexpr std::size_t kMaxWatched = 64;      // bodies in one pose frame's watched records
inline constexpr double kWatchLifetime = 3;         // s: a page's watch lapses unless re-sent
// Whether a state of this many bodies goes to the page in float32, and its bytes per body.
bool state_in_float32(std::size_t bodies);
inline std::size_t state_bytes_per_body(std::size_t bodies) {
  return 13 * (state_in_float32(bodies) ? 4 : 8) + 2 * 4 + 4;
}
// Accepted wrenches forwarded to the pages: at most this many per message (the newest), at most
// kWrenchRate messages a second (rigid-view keeps the newest per source, body and key).
inline constexpr std::size_t kMaxWrenchesShown = 64;
inline constexpr double kWrenchRate = 20;
inline constexpr std::size_t kMaxCommandBytes = 512;
// A page acknowledges each state frame once it has drawn it; rigid-view sends a page at most
// kMaxUnackedStates frames (and kMaxUnackedBytes) ahead of its acks (server.hpp), so a slow page's
// states wait (newest only) in rigid-view instead of in TCP buffers, where they would add seconds
// of latency.
inline constexpr std::string_view kAckCommand = R"({"op":"ack"})";
inline constexpr std::int64_t kMaxSteps = 1'000'000;
inline constexpr std::int64_t kMaxCommandId = (std::int64_t{1} << 53);  // exact in JavaScript
inline constexpr double kMaxPushForce = 1e4;  // N; rigidd's limits.max_force still applies
inline constexpr double kMaxPushPoint = 100;  // m from the centre of mass
inline constexpr double kMaxEditValue =
    1e9;  // |component| of a set_state's vectors (m, m/s, rad/s)
// Playback (rigid-view FILE): the speed range, and the largest |time| a seek may name (s).
inline constexpr double kMinPlaybackSpeed = 1.0 / 64;
inline constexpr double kMaxPlaybackSpeed = 64;
inline constexpr double kMaxSeekTime = 1e12;

// The state as the page reads it, with each body's drifts in the state's order (DriftTracker;
// missing ones are sent as 0).
std::string encode_state(const StateFrame& state, std::uint32_t scene_generation,
                         const std::vector<float>& energy_drift,
                         const std::vector<float>& momentum_drift);
// The pose frame of a live state (see the top), with the records of the bodies of `watched` (ids,
// at most kMaxWatched, each once) that the state holds, in the order given.
std::string encode_pose_state(const StateFrame& state, std::uint32_t scene_generation,
                              const std::vector<float>& energy_drift,
                              const std::vector<float>& momentum_drift,
                              const std::vector<std::int32_t>& watched);
inline std::size_t pose_state_bytes(std::size_t bodies, std::size_t watched) {
  return kStateHeaderBytes + kPoseBytesPerBody * bodies + kPoseTrailerBytes +
         kWatchedRecordBytes * watched;
}

// {"type":"scene", ...}: each body's id, name and what to draw: "box" (size), "sphere",
// "cylinder", "capsule", "ellipsoid" (dims as in SceneDescription), or for a body without a shape
// the uniform box with its principal moments ("box", size, and "frame": the principal axes in B
// as w, x, y, z); and for the page's energy and momentum: "mass" and "inertia" (Ixx, Iyy, Izz,
// Ixy, Ixz, Iyz about the CoM, in B), and the scene's "gravity" (W); and its limits on a command,
// "max_force" and "max_torque" (<= 0: none), which bound the page's pushes. A scene with static
// parts also has "parts": each one's name, "shape" ("plane", "box", "sphere", "cylinder",
// "capsule"), pose "p" (p_WS) and "q" (q_WS: w, x, y, z) and "dims" (as a body's; a plane is z = 0
// of S).
std::string scene_json(const SceneDescription& scene, std::uint64_t generation);
std::string stats_json(const StatsReport& stats);
// {"type":"wrenches","wrenches":[{"body":ID,"tick":T,"ttl":S,"force":[..],"force_frame":"world"|
// "body","point":[..],"torque":[..],"torque_frame":..,"key":K[,"until":U]}, ...]}: the accepted
// wrenches (kind kWrench; others skipped), at most kMaxWrenchesShown, the last ones of `accepted`.
// A wrench accepted at tick k acts on the steps that produce the states k+1 .. k+n, n = rigidd's
// ticks_to_live(ttl, dt) (the page draws it with those states). `until`, when not empty, has one
// entry per element of `accepted`: the last tick it acts on when that is earlier (playback knows
// when a recorded wrench was replaced or cleared by a reset).
std::string wrenches_json(const std::vector<AcceptedCommand>& accepted,
                          const std::vector<std::int64_t>& until = {});
// {"type":"hello","read_only":B,"connection":N,"mode":"live"|"playback"}
std::string hello_json(bool read_only, std::uint64_t connection, bool playback = false);
// {"type":"reply","id":N,"op":"pause","ok":B,"outcome":"ok","tick":T,"message":"..."}
std::string reply_json(std::int64_t id, std::string_view op, bool ok, std::string_view outcome,
                       std::int64_t tick, std::string_view message);
// {"type":"error","message":"..."}: a refused frame.
std::string error_json(std::string_view message);

// Playback (rigid-view FILE): where it is, for the page's timeline. {"type":"playback",
// "file":"...","playing":B,"speed":X,"start":S,"end":S,"position":S,"tick":T,"sim_time":S,
// "index":I,"states":N}: start, end and position on the recording's timeline (its sim time, carried
// on across a reset in the recording); tick, sim_time and index of the state shown.
struct PlaybackStatus {
  std::string_view file;
  bool playing = false;
  double speed = 1;
  double start = 0, end = 0, position = 0;
  std::int64_t tick = 0;
  double sim_time = 0;
  std::size_t index = 0, states = 0;
};
std::string playback_json(const PlaybackStatus& status);

enum class Op {
  kPause,
  kResume,
  kStep,
  kReset,
  kPush,
  kPlay,
  kSeek,
  kSpeed,
  kWatch,
  kSetState,
  kResetBody
};
std::string_view op_name(Op op);

struct PageCommand {
  Op op = Op::kPause;
  std::int64_t id = 0;
  std::int64_t steps = 0;  // kStep
  std::int32_t body = -1;  // kPush, kSetState, kResetBody; kWatch (-1: none)
  rigid::Vec3 force{};     // kPush
  rigid::Vec3 point{};     // kPush
  double ttl = 0;  // kPush from a Foxglove client: its duration (s); 0: the page's re-sent push
  rigid::StateEdit state;  // kSetState: the parts given (set), in the world frame
  // Playback. kSeek: exactly one of tick (>= 0) and time (finite); the other stays at its default.
  std::int64_t tick = -1;
  std::optional<double> time;
  double speed = 0;  // kSpeed, in [kMinPlaybackSpeed, kMaxPlaybackSpeed]
  bool operator==(const PageCommand&) const = default;
};

// The command, or one line saying why the text is refused.
std::variant<PageCommand, std::string> parse_command(std::string_view text);
// Why a valid command is refused in this mode ("" when it is not): rigidd's controls other than
// pause, pushes and edits have no rigidd to go to while playing a recording; play, seek and speed
// have no recording to act on in live mode.
std::string refusal_in_mode(const PageCommand& command, bool playback);

// The uniform box with the same principal moments as `inertia` (Ixx, Iyy, Izz, Ixy, Ixz, Iyz) and
// `mass`: its edge lengths and the principal axes in B (w, x, y, z). Exposed for the tests.
struct MomentBox {
  rigid::Vec3 size{};
  std::array<double, 4> frame{1, 0, 0, 0};
};
MomentBox box_of_moments(double mass, const double* inertia);

}  // namespace rigid::view
