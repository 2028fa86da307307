// The messages rigid exchanges, as plain C++ values: their one home, shared by the loop, the
// transports, the record files, rigid's tools and every client built on the SDK (installed as
// <rigid/messages.hpp>). Each bus adapter converts these to and from its generated types
// (msgs/rigid.idl, msgs/rigid.lcm carry the same fields; read rigid.idl for units and frames).
// Nothing here knows about DDS, LCM or the physics core (which keeps its own Eigen types).
//
// Per-body values are flat and interleaved per body, as on the wire: body i's position is
// position[3 i .. 3 i + 2], its orientation (w, x, y, z) is orientation[4 i .. 4 i + 3]. Decoders
// guarantee these lengths agree with ids.size(); publishers expect the same.
//
// Enumerations carry whatever integer arrived: a value outside the named ones is passed through
// unchanged, and rejecting it is the receiver's (the loop's) decision, so it can be counted.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace rigid {

// The two buses rigid speaks; a message carries the same fields on both.
enum class Bus : std::uint8_t { kDds, kLcm };

inline std::string_view to_string(Bus bus) {
  return bus == Bus::kDds ? "dds" : "lcm";
}

enum class Frame : std::int32_t { kWorld = 0, kBody = 1 };

enum class ControlKind : std::int32_t {
  kNone = 0,  // what a zero-initialized message asks for: nothing, so it is rejected
  kPause = 1,
  kResume = 2,
  kStep = 3,
  kReset = 4,
  kSetRtf = 5,
};

enum class Outcome : std::int32_t { kOk = 0, kInvalid = 1, kNotAllowed = 2, kFailed = 3 };

// ControlReply.command of the answer to a refused wrench (msgs/rigid.idl REPLY_WRENCH).
inline constexpr ControlKind kReplyToWrench = static_cast<ControlKind>(100);
// ControlReply.command of the answer to an edit (msgs/rigid.idl REPLY_EDIT).
inline constexpr ControlKind kReplyToEdit = static_cast<ControlKind>(101);

// What an edit of the running world does (EditCommand.kind). One command family: spawning and
// removing bodies and loading another scene are to join it as further kinds.
enum class EditKind : std::int32_t {
  kNone = 0,       // what a zero-initialized message asks for: nothing, so it is refused
  kSetState = 1,   // sets the parts of one body's state that StateEdit::set names
  kResetBody = 2,  // puts one body back to its scene state and drops the wrenches acting on it
};

// StateEdit::set: the parts of the state a kSetState sets; the others keep their values.
inline constexpr std::int32_t kSetPosition = 1;
inline constexpr std::int32_t kSetOrientation = 2;
inline constexpr std::int32_t kSetLinearVelocity = 4;
inline constexpr std::int32_t kSetAngularVelocity = 8;
inline constexpr std::int32_t kSetAll = 15;

enum class Mode : std::int32_t { kRealtime = 0, kFast = 1, kLockstep = 2 };

enum class ShapeKind : std::int32_t {
  kNone = 0,
  kSphere = 1,     // dims: radius
  kBox = 2,        // dims: full side lengths along B's x, y, z
  kCylinder = 3,   // dims: radius, length along B's z
  kEllipsoid = 4,  // dims: semi-axes along B's x, y, z
  kCapsule = 5,    // dims: radius, length of the cylindrical part along B's z
  // Static parts only (SceneDescription::part_kinds): the plane z = 0 of the part's frame, solid
  // below it (z <= 0); dims unused.
  kPlane = 6,
};

// What a contact event is (ContactEvents::kinds).
enum class ContactKind : std::int32_t {
  kImpact = 1,    // an impulse where a body hit a static part
  kResting = 2,   // the body starts resting on its supports: no velocity, held by them
  kSliding = 3,   // the body starts sliding on its supports (slip at a contact)
  kRolling = 4,   // the body starts moving on its supports without slip at any contact
  kSeparate = 5,  // the body leaves its supports: in free flight from here
};

using Vec3 = std::array<double, 3>;

// The bounds msgs/rigid.idl puts on what travels (a longer string or sequence is dropped by the
// reader's deserializer on DDS, refused by the codecs on LCM).
inline constexpr std::size_t kMaxBodies = 1'000'000;
inline constexpr std::size_t kMaxNameLength = 128;     // body names, in scenes and on the wire
inline constexpr std::size_t kMaxMessageLength = 256;  // ControlReply.message, scene_name
inline constexpr std::size_t kMaxIntegratorLength = 64;
inline constexpr std::size_t kMaxRefusedSources = 16;  // StatsReport.refused_by_source
inline constexpr std::size_t kMaxSenderLength = 80;
inline constexpr std::size_t kMaxReasonLength = 24;
// Static parts a scene description may carry, and contact events one ContactEvents message may
// carry: the physics keeps at most this many a tick (physics::World::contact_events).
inline constexpr std::size_t kMaxParts = 1'000'000;
inline constexpr std::size_t kMaxContactEvents = 4096;

// One published state of the world (server -> all).
struct StateFrame {
  std::int64_t tick = 0;
  double sim_time = 0.0;      // tick * dt (s)
  std::int64_t stamp_ns = 0;  // wall clock (CLOCK_REALTIME) when handed to the buses
  std::vector<std::int32_t> ids;
  std::vector<double> position;          // 3n: p_WBo
  std::vector<double> orientation;       // 4n: q_WB as w, x, y, z
  std::vector<double> linear_velocity;   // 3n: v_WBo in W
  std::vector<double> angular_velocity;  // 3n: w_WB in W

  std::size_t body_count() const { return ids.size(); }
  // Sizes every per-body vector for n bodies; keeps capacity, so a reused frame stops allocating.
  void resize(std::size_t n) {
    ids.resize(n);
    position.resize(3 * n);
    orientation.resize(4 * n);
    linear_velocity.resize(3 * n);
    angular_velocity.resize(3 * n);
  }
  bool lengths_agree() const {
    const std::size_t n = ids.size();
    return position.size() == 3 * n && orientation.size() == 4 * n &&
           linear_velocity.size() == 3 * n && angular_velocity.size() == 3 * n;
  }
  bool operator==(const StateFrame&) const = default;
};

// A wrench: a force at a body-local point, plus an optional pure torque, acting for ttl. Its one
// home: the command a controller sends, the command the server accepted, the loop's table of
// acting wrenches and its journal hold it as this base, and the converters (transport/
// wire_fields.hpp, common/log_records.cpp), the view's JSON and Python's dicts read and write it
// once as a whole, so that a new field is added here and where those spell it out.
struct Wrench {
  Vec3 force{};  // N, in force_frame
  Vec3 point{};  // application point from the centre of mass, in B (m)
  Frame force_frame = Frame::kWorld;
  Vec3 torque{};  // N m, in torque_frame; zero for none
  Frame torque_frame = Frame::kWorld;
  double ttl = 0.0;  // s; 0: one tick

  const Wrench& wrench() const { return *this; }
  Wrench& wrench() { return *this; }
  bool operator==(const Wrench&) const = default;
};

// A body's state as an edit sets it: its one home, as Wrench is a wrench's (the command a client
// sends, the command the server accepted, the loop's journal). Velocities in a body frame are
// expressed in B as it is oriented after the edit (the new orientation when the edit sets one).
struct StateEdit {
  std::int32_t set = 0;                           // kSet* bits
  Vec3 position{};                                // p_WBo (m)
  std::array<double, 4> orientation{1, 0, 0, 0};  // q_WB as w, x, y, z; normalised when applied
  Vec3 linear_velocity{};                         // v_WBo (m/s), in velocity_frame
  Frame velocity_frame = Frame::kWorld;
  Vec3 angular_velocity{};  // w_WB (rad/s), in angular_velocity_frame
  Frame angular_velocity_frame = Frame::kWorld;

  const StateEdit& state_edit() const { return *this; }
  StateEdit& state_edit() { return *this; }
  bool operator==(const StateEdit&) const = default;
};

// An edit of the running world (client -> server): one body's state set, or one body reset. It
// takes effect between two ticks and is answered on the control reply topic (kReplyToEdit).
struct EditCommand : StateEdit {
  std::int64_t source = 0;
  std::int64_t seq = 0;
  EditKind kind = EditKind::kNone;
  std::int32_t body_id = -1;  // < 0: the body is named by body_name
  std::string body_name;
  std::int64_t stamp_ns = 0;

  bool operator==(const EditCommand&) const = default;
};

// A wrench on one body (controller -> server). The same (source, body, key) replaces the previous
// wrench; it acts until ttl runs out (0: one tick).
struct WrenchCommand : Wrench {
  std::int64_t source = 0;
  std::int64_t seq = 0;
  std::int32_t key = 0;
  std::int32_t body_id = -1;  // < 0: the body is named by body_name
  std::string body_name;
  std::int64_t stamp_ns = 0;

  bool operator==(const WrenchCommand&) const = default;
};

// pause / resume / step N / reset / set real-time factor (client -> server).
struct ControlCommand {
  std::int64_t source = 0;
  std::int64_t seq = 0;
  ControlKind command = ControlKind::kNone;
  std::int64_t steps = 0;  // kStep
  double rtf = 0.0;        // kSetRtf

  bool operator==(const ControlCommand&) const = default;
};

// The answer to one ControlCommand (server -> clients), echoing its source and seq.
struct ControlReply {
  std::int64_t source = 0;
  std::int64_t seq = 0;
  ControlKind command = ControlKind::kNone;
  Outcome outcome = Outcome::kOk;
  std::int64_t tick = 0;
  std::string message;  // why, when outcome != kOk

  bool operator==(const ControlReply&) const = default;
};

enum class AcceptedKind : std::int32_t { kWrench = 1, kControl = 2, kEdit = 3 };

// A command the server accepted, once, with the tick at which it took effect (server -> all): a
// wrench that entered the table of acting wrenches (it acts from the step that starts at `tick`),
// a control request carried out, or an edit made (before the step that starts at `tick`). The
// Wrench base holds the wrench as the server applies it (its body resolved to an id); the control
// fields are set for kControl; for kEdit, `edit`, body_id and the StateEdit base.
struct AcceptedCommand : Wrench, StateEdit {
  std::int64_t tick = 0;
  AcceptedKind kind = AcceptedKind::kWrench;
  std::int64_t source = 0;
  std::int64_t seq = 0;
  std::int32_t key = 0;
  std::int32_t body_id = 0;
  ControlKind command = ControlKind::kNone;
  std::int64_t steps = 0;
  double rtf = 0.0;
  EditKind edit = EditKind::kNone;
  std::int64_t stamp_ns = 0;

  bool operator==(const AcceptedCommand&) const = default;
};

// Commands the server refused, by reason.
struct RejectCounts {
  std::int64_t non_finite = 0;
  std::int64_t unknown_body = 0;
  std::int64_t over_limit = 0;
  std::int64_t undecodable = 0;
  std::int64_t stale_sequence = 0;
  std::int64_t queue_full = 0;
  std::int64_t invalid = 0;
  std::int64_t over_share = 0;
  std::int64_t rate_limited = 0;
  std::int64_t not_permitted = 0;

  bool operator==(const RejectCounts&) const = default;
};

// One of the senders with the most refused commands (StatsReport.refused_by_source).
struct SourceRefusals {
  std::string sender;       // identity, or bus and session ("dds:1f2e...", "lcm:127.0.0.1:40000")
  std::int64_t count = 0;   // refused since start
  std::string last_reason;  // a RejectCounts field name

  bool operator==(const SourceRefusals&) const = default;
};

// The traffic of one bus.
struct TransportCounts {
  std::int64_t sent = 0;
  std::int64_t send_failures = 0;
  std::int64_t received = 0;
  std::int64_t decode_failures = 0;

  bool operator==(const TransportCounts&) const = default;
};

// Loop health, once a second (server -> all).
struct StatsReport {
  std::int64_t tick = 0;
  double sim_time = 0.0;
  Mode mode = Mode::kRealtime;
  bool paused = false;
  double rtf_last_second = 0.0;
  double rtf_since_start = 0.0;
  double lateness_p50_us = 0.0;
  double lateness_p99_us = 0.0;
  double lateness_max_us = 0.0;
  std::int64_t overruns = 0;
  double step_cost_p50_us = 0.0;
  double step_cost_max_us = 0.0;
  std::int64_t bodies_frozen = 0;         // by the physics guard, now (a reset thaws them)
  std::int64_t large_rotation_steps = 0;  // body-steps turning by more than pi, since start
  std::int64_t states_skipped = 0;
  std::int64_t commands_accepted = 0;
  RejectCounts rejected;
  TransportCounts dds;
  TransportCounts lcm;
  std::vector<SourceRefusals> refused_by_source;  // at most kMaxRefusedSources, most first

  bool operator==(const StatsReport&) const = default;
};

// What the scene holds (server -> all; late joiners get it).
struct SceneDescription {
  std::string scene_name;
  double dt = 0.0;  // tick period (s)
  std::int32_t substeps = 1;
  std::int32_t publish_every = 1;
  Vec3 gravity{};
  std::string integrator;
  double max_force = 0.0;  // <= 0: unlimited
  double max_torque = 0.0;
  double max_ttl = 0.0;                      // s
  std::int32_t max_wrenches_per_source = 0;  // live wrenches one sender may hold
  double max_commands_per_second = 0.0;      // per sender
  std::vector<std::int32_t> ids;
  std::vector<std::string> names;
  std::vector<double> masses;
  std::vector<double> inertia;  // 6n: Ixx, Iyy, Izz, Ixy, Ixz, Iyz about the centre of mass, in B
  std::vector<ShapeKind> shape_kinds;
  std::vector<double> shape_dims;  // 3n
  // Static parts, m of them: the scene's planes, then its static shapes, in file order (a contact
  // event's part is an index into these). Each has a frame S fixed in W: a plane is the plane
  // z = 0 of S, solid below it (S's origin is the plane's point nearest W's origin, its z axis the
  // plane's unit normal); a shape is centred on S's origin with its axes along S's.
  std::vector<std::string> part_names;
  std::vector<ShapeKind> part_kinds;     // kPlane, kBox, kSphere, kCylinder, kCapsule
  std::vector<double> part_position;     // 3m: p_WS
  std::vector<double> part_orientation;  // 4m: q_WS as w, x, y, z
  std::vector<double> part_dims;         // 3m: as shape_dims; 0 for a plane
  std::vector<double> part_restitution;  // m: its material (the world's where it gave none)
  std::vector<double> part_friction;     // m

  std::size_t body_count() const { return ids.size(); }
  std::size_t part_count() const { return part_names.size(); }
  bool lengths_agree() const {
    const std::size_t n = ids.size();
    const std::size_t m = part_names.size();
    return names.size() == n && masses.size() == n && inertia.size() == 6 * n &&
           shape_kinds.size() == n && shape_dims.size() == 3 * n && part_kinds.size() == m &&
           part_position.size() == 3 * m && part_orientation.size() == 4 * m &&
           part_dims.size() == 3 * m && part_restitution.size() == m && part_friction.size() == m;
  }
  bool operator==(const SceneDescription&) const = default;
};

// The contact events of one tick (server -> all), published for the ticks that have any: every
// impact of a body on a static part, and every change of how the parts support a body (it starts
// resting, sliding or rolling, or leaves them), in the order the physics found them (by step, body
// id, then time). n events, at most kMaxContactEvents.
struct ContactEvents {
  std::int64_t tick = 0;      // the tick whose steps they happened in (from tick - 1 to tick)
  double sim_time = 0.0;      // tick * dt: the end of that tick (s)
  std::int64_t stamp_ns = 0;  // wall clock (CLOCK_REALTIME) when handed to the buses
  // Events the server could not send on this bus since it started: beyond kMaxContactEvents in a
  // tick (the physics keeps no more), or while the bus's publisher was behind.
  std::int64_t dropped = 0;
  std::vector<ContactKind> kinds;
  std::vector<std::int32_t> bodies;  // body ids
  // Static part indices (SceneDescription::part_names); -1 for a separate event (the body leaves
  // all its supports at once: no one part).
  std::vector<std::int32_t> parts;
  std::vector<double> times;     // n: sim time of each, exactly, within the tick (s)
  std::vector<double> position;  // 3n: p_W, where (an impact: the impulse's centre)
  std::vector<double> normal;    // 3n: n_W, the part's unit normal there, towards the body
  std::vector<double> impulse;   // 3n: on the body, in W (N s); zero but for an impact

  std::size_t event_count() const { return kinds.size(); }
  // Sizes every per-event vector for n events; keeps capacity.
  void resize(std::size_t n) {
    kinds.resize(n);
    bodies.resize(n);
    parts.resize(n);
    times.resize(n);
    position.resize(3 * n);
    normal.resize(3 * n);
    impulse.resize(3 * n);
  }
  bool lengths_agree() const {
    const std::size_t n = kinds.size();
    return bodies.size() == n && parts.size() == n && times.size() == n &&
           position.size() == 3 * n && normal.size() == 3 * n && impulse.size() == 3 * n;
  }
  bool operator==(const ContactEvents&) const = default;
};

}  // namespace rigid
