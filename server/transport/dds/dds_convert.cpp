#include "transport/dds/dds_convert.hpp"

#include <algorithm>
#include <cstddef>
#include <cstring>
#include <limits>
#include <string>

namespace rigid::transport::dds {
namespace {

// The writer only reads the buffer, so lending a const vector's storage is safe; _release = false
// tells Cyclone it does not own it.
template <class Seq, class T>
void lend(const std::vector<T>& in, Seq& out) {
  out._maximum = static_cast<std::uint32_t>(in.size());
  out._length = out._maximum;
  out._buffer = const_cast<T*>(in.data());
  out._release = false;
}

template <class T, class Seq>
void copy_seq(const Seq& in, std::vector<T>& out) {
  if (in._buffer == nullptr) {
    out.clear();
    return;
  }
  out.assign(in._buffer, in._buffer + in._length);
}

// Bounded IDL strings are fixed arrays in the C binding (string<N> is char[N + 1]). A string that
// does not fit is refused rather than cut (the caller returns false: kInvalid).
template <std::size_t N>
bool put_string(const std::string& in, char (&out)[N]) {
  if (in.size() >= N) return false;
  std::copy(in.begin(), in.end(), out);
  out[in.size()] = '\0';
  return true;
}

template <std::size_t N>
void copy_string(const char (&in)[N], std::string& out) {
  out.assign(in, strnlen(in, N));
}

void copy3(const Vec3& in, double (&out)[3]) {
  std::copy(in.begin(), in.end(), out);
}
void copy3(const double (&in)[3], Vec3& out) {
  std::copy(std::begin(in), std::end(in), out.begin());
}

}  // namespace

bool borrow(const StateFrame& in, BorrowScratch& /*scratch*/, rigid_WorldState& out) {
  if (!in.lengths_agree() || in.body_count() > kMaxBodies) return false;
  out.tick = in.tick;
  out.sim_time = in.sim_time;
  out.stamp_ns = in.stamp_ns;
  lend(in.ids, out.ids);
  lend(in.position, out.position);
  lend(in.orientation, out.orientation);
  lend(in.linear_velocity, out.linear_velocity);
  lend(in.angular_velocity, out.angular_velocity);
  return true;
}

DecodeStatus copy_from(const rigid_WorldState& in, StateFrame& out) {
  const std::size_t n = in.ids._length;
  if (in.position._length != 3 * n || in.orientation._length != 4 * n ||
      in.linear_velocity._length != 3 * n || in.angular_velocity._length != 3 * n) {
    return DecodeStatus::kInconsistentLengths;
  }
  out.tick = in.tick;
  out.sim_time = in.sim_time;
  out.stamp_ns = in.stamp_ns;
  copy_seq(in.ids, out.ids);
  copy_seq(in.position, out.position);
  copy_seq(in.orientation, out.orientation);
  copy_seq(in.linear_velocity, out.linear_velocity);
  copy_seq(in.angular_velocity, out.angular_velocity);
  return DecodeStatus::kOk;
}

bool borrow(const WrenchCommand& in, BorrowScratch& /*scratch*/, rigid_Wrench& out) {
  out.source = in.source;
  out.seq = in.seq;
  out.key = in.key;
  out.body_id = in.body_id;
  if (!put_string(in.body_name, out.body_name)) return false;
  copy3(in.force, out.force);
  copy3(in.point, out.point);
  out.force_frame = static_cast<std::int32_t>(in.force_frame);
  copy3(in.torque, out.torque);
  out.torque_frame = static_cast<std::int32_t>(in.torque_frame);
  out.ttl = in.ttl;
  out.stamp_ns = in.stamp_ns;
  return true;
}

DecodeStatus copy_from(const rigid_Wrench& in, WrenchCommand& out) {
  out.source = in.source;
  out.seq = in.seq;
  out.key = in.key;
  out.body_id = in.body_id;
  copy_string(in.body_name, out.body_name);
  copy3(in.force, out.force);
  copy3(in.point, out.point);
  out.force_frame = static_cast<Frame>(in.force_frame);
  copy3(in.torque, out.torque);
  out.torque_frame = static_cast<Frame>(in.torque_frame);
  out.ttl = in.ttl;
  out.stamp_ns = in.stamp_ns;
  return DecodeStatus::kOk;
}

bool borrow(const ControlCommand& in, BorrowScratch& /*scratch*/, rigid_Control& out) {
  out.source = in.source;
  out.seq = in.seq;
  out.command = static_cast<std::int32_t>(in.command);
  out.steps = in.steps;
  out.rtf = in.rtf;
  return true;
}

DecodeStatus copy_from(const rigid_Control& in, ControlCommand& out) {
  out.source = in.source;
  out.seq = in.seq;
  out.command = static_cast<ControlKind>(in.command);
  out.steps = in.steps;
  out.rtf = in.rtf;
  return DecodeStatus::kOk;
}

bool borrow(const ControlReply& in, BorrowScratch& /*scratch*/, rigid_ControlReply& out) {
  out.source = in.source;
  out.seq = in.seq;
  out.command = static_cast<std::int32_t>(in.command);
  out.outcome = static_cast<std::int32_t>(in.outcome);
  out.tick = in.tick;
  if (!put_string(in.message, out.message)) return false;
  return true;
}

DecodeStatus copy_from(const rigid_ControlReply& in, ControlReply& out) {
  out.source = in.source;
  out.seq = in.seq;
  out.command = static_cast<ControlKind>(in.command);
  out.outcome = static_cast<Outcome>(in.outcome);
  out.tick = in.tick;
  copy_string(in.message, out.message);
  return DecodeStatus::kOk;
}

bool borrow(const StatsReport& in, BorrowScratch& scratch, rigid_Stats& out) {
  const std::size_t n = in.refused_by_source.size();
  if (n > kMaxRefusedSources) return false;
  scratch.senders.resize(n);
  scratch.reasons.resize(n);
  scratch.counts.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const SourceRefusals& r = in.refused_by_source[i];
    if (!put_string(r.sender,
                    *reinterpret_cast<char(*)[kMaxSenderLength + 1]>(scratch.senders[i].data())) ||
        !put_string(r.last_reason,
                    *reinterpret_cast<char(*)[kMaxReasonLength + 1]>(scratch.reasons[i].data()))) {
      return false;
    }
    scratch.counts[i] = r.count;
  }
  out.refused_sender = {static_cast<std::uint32_t>(n), static_cast<std::uint32_t>(n),
                        reinterpret_cast<char(*)[kMaxSenderLength + 1]>(scratch.senders.data()),
                        false};
  out.refused_last_reason = {
      static_cast<std::uint32_t>(n), static_cast<std::uint32_t>(n),
      reinterpret_cast<char(*)[kMaxReasonLength + 1]>(scratch.reasons.data()), false};
  lend(scratch.counts, out.refused_count);
  out.tick = in.tick;
  out.sim_time = in.sim_time;
  out.mode = static_cast<std::int32_t>(in.mode);
  out.paused = in.paused;
  out.rtf_last_second = in.rtf_last_second;
  out.rtf_since_start = in.rtf_since_start;
  out.lateness_p50_us = in.lateness_p50_us;
  out.lateness_p99_us = in.lateness_p99_us;
  out.lateness_max_us = in.lateness_max_us;
  out.overruns = in.overruns;
  out.step_cost_p50_us = in.step_cost_p50_us;
  out.step_cost_max_us = in.step_cost_max_us;
  out.bodies_frozen = in.bodies_frozen;
  out.large_rotation_steps = in.large_rotation_steps;
  out.states_skipped = in.states_skipped;
  out.commands_accepted = in.commands_accepted;
  out.rejected = {in.rejected.non_finite,   in.rejected.unknown_body,   in.rejected.over_limit,
                  in.rejected.undecodable,  in.rejected.stale_sequence, in.rejected.queue_full,
                  in.rejected.invalid,      in.rejected.over_share,     in.rejected.rate_limited,
                  in.rejected.not_permitted};
  out.dds = {in.dds.sent, in.dds.send_failures, in.dds.received, in.dds.decode_failures};
  out.lcm = {in.lcm.sent, in.lcm.send_failures, in.lcm.received, in.lcm.decode_failures};
  return true;
}

DecodeStatus copy_from(const rigid_Stats& in, StatsReport& out) {
  out.tick = in.tick;
  out.sim_time = in.sim_time;
  out.mode = static_cast<Mode>(in.mode);
  out.paused = in.paused;
  out.rtf_last_second = in.rtf_last_second;
  out.rtf_since_start = in.rtf_since_start;
  out.lateness_p50_us = in.lateness_p50_us;
  out.lateness_p99_us = in.lateness_p99_us;
  out.lateness_max_us = in.lateness_max_us;
  out.overruns = in.overruns;
  out.step_cost_p50_us = in.step_cost_p50_us;
  out.step_cost_max_us = in.step_cost_max_us;
  out.bodies_frozen = in.bodies_frozen;
  out.large_rotation_steps = in.large_rotation_steps;
  out.states_skipped = in.states_skipped;
  out.commands_accepted = in.commands_accepted;
  out.rejected = {in.rejected.non_finite,   in.rejected.unknown_body,   in.rejected.over_limit,
                  in.rejected.undecodable,  in.rejected.stale_sequence, in.rejected.queue_full,
                  in.rejected.invalid,      in.rejected.over_share,     in.rejected.rate_limited,
                  in.rejected.not_permitted};
  out.dds = {in.dds.sent, in.dds.send_failures, in.dds.received, in.dds.decode_failures};
  out.lcm = {in.lcm.sent, in.lcm.send_failures, in.lcm.received, in.lcm.decode_failures};
  const std::size_t n = in.refused_sender._length;
  if (in.refused_count._length != n || in.refused_last_reason._length != n) {
    return DecodeStatus::kInconsistentLengths;
  }
  out.refused_by_source.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    copy_string(in.refused_sender._buffer[i], out.refused_by_source[i].sender);
    out.refused_by_source[i].count = in.refused_count._buffer[i];
    copy_string(in.refused_last_reason._buffer[i], out.refused_by_source[i].last_reason);
  }
  return DecodeStatus::kOk;
}

bool borrow(const SceneDescription& in, BorrowScratch& scratch, rigid_SceneInfo& out) {
  if (!in.lengths_agree() || in.body_count() > kMaxBodies) return false;
  out.dt = in.dt;
  out.substeps = in.substeps;
  out.publish_every = in.publish_every;
  copy3(in.gravity, out.gravity);
  if (!put_string(in.scene_name, out.scene_name) || !put_string(in.integrator, out.integrator)) {
    return false;
  }
  out.max_force = in.max_force;
  out.max_torque = in.max_torque;
  out.max_ttl = in.max_ttl;
  out.max_wrenches_per_source = in.max_wrenches_per_source;
  out.max_commands_per_second = in.max_commands_per_second;
  lend(in.ids, out.ids);
  scratch.names.resize(in.names.size());
  for (std::size_t i = 0; i < in.names.size(); ++i) {
    if (!put_string(in.names[i],
                    *reinterpret_cast<char(*)[kMaxNameLength + 1]>(scratch.names[i].data()))) {
      return false;
    }
  }
  out.names = {static_cast<std::uint32_t>(in.names.size()),
               static_cast<std::uint32_t>(in.names.size()),
               reinterpret_cast<char(*)[kMaxNameLength + 1]>(scratch.names.data()), false};
  lend(in.masses, out.masses);
  lend(in.inertia, out.inertia);
  scratch.shape_kinds.resize(in.shape_kinds.size());
  std::transform(in.shape_kinds.begin(), in.shape_kinds.end(), scratch.shape_kinds.begin(),
                 [](ShapeKind kind) { return static_cast<std::int32_t>(kind); });
  lend(scratch.shape_kinds, out.shape_kinds);
  lend(in.shape_dims, out.shape_dims);
  return true;
}

DecodeStatus copy_from(const rigid_SceneInfo& in, SceneDescription& out) {
  const std::size_t n = in.ids._length;
  if (in.names._length != n || in.masses._length != n || in.inertia._length != 6 * n ||
      in.shape_kinds._length != n || in.shape_dims._length != 3 * n) {
    return DecodeStatus::kInconsistentLengths;
  }
  copy_string(in.scene_name, out.scene_name);
  out.dt = in.dt;
  out.substeps = in.substeps;
  out.publish_every = in.publish_every;
  copy3(in.gravity, out.gravity);
  copy_string(in.integrator, out.integrator);
  out.max_force = in.max_force;
  out.max_torque = in.max_torque;
  out.max_ttl = in.max_ttl;
  out.max_wrenches_per_source = in.max_wrenches_per_source;
  out.max_commands_per_second = in.max_commands_per_second;
  copy_seq(in.ids, out.ids);
  out.names.resize(n);
  for (std::size_t i = 0; i < n; ++i)
    copy_string(in.names._buffer[i], out.names[i]);
  copy_seq(in.masses, out.masses);
  copy_seq(in.inertia, out.inertia);
  out.shape_kinds.resize(n);
  std::transform(in.shape_kinds._buffer, in.shape_kinds._buffer + n, out.shape_kinds.begin(),
                 [](std::int32_t kind) { return static_cast<ShapeKind>(kind); });
  copy_seq(in.shape_dims, out.shape_dims);
  return DecodeStatus::kOk;
}

bool borrow(const AcceptedCommand& in, BorrowScratch& /*scratch*/, rigid_AcceptedCommand& out) {
  out.tick = in.tick;
  out.kind = static_cast<std::int32_t>(in.kind);
  out.source = in.source;
  out.seq = in.seq;
  out.key = in.key;
  out.body_id = in.body_id;
  copy3(in.force, out.force);
  copy3(in.point, out.point);
  out.force_frame = static_cast<std::int32_t>(in.force_frame);
  copy3(in.torque, out.torque);
  out.torque_frame = static_cast<std::int32_t>(in.torque_frame);
  out.ttl = in.ttl;
  out.command = static_cast<std::int32_t>(in.command);
  out.steps = in.steps;
  out.rtf = in.rtf;
  out.stamp_ns = in.stamp_ns;
  return true;
}

DecodeStatus copy_from(const rigid_AcceptedCommand& in, AcceptedCommand& out) {
  out.tick = in.tick;
  out.kind = static_cast<AcceptedKind>(in.kind);
  out.source = in.source;
  out.seq = in.seq;
  out.key = in.key;
  out.body_id = in.body_id;
  copy3(in.force, out.force);
  copy3(in.point, out.point);
  out.force_frame = static_cast<Frame>(in.force_frame);
  copy3(in.torque, out.torque);
  out.torque_frame = static_cast<Frame>(in.torque_frame);
  out.ttl = in.ttl;
  out.command = static_cast<ControlKind>(in.command);
  out.steps = in.steps;
  out.rtf = in.rtf;
  out.stamp_ns = in.stamp_ns;
  return DecodeStatus::kOk;
}

}  // namespace rigid::transport::dds
