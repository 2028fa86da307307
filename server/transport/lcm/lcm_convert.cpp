#include "transport/lcm/lcm_convert.hpp"

#include <algorithm>
#include <cstddef>
#include <limits>
#include <vector>

namespace rigid::transport::lcm {
namespace {

std::int32_t count(std::size_t n) {
  return static_cast<std::int32_t>(n);
}

// lcm-gen's decoder leaves an array untouched when its count is 0, so a reused message may hold a
// previous message's elements past the count: copy exactly `count` of them.
template <class T, class U>
void copy_prefix(const std::vector<T>& in, std::size_t count, std::vector<U>& out) {
  out.assign(in.begin(), in.begin() + static_cast<std::ptrdiff_t>(count));
}

void copy3(const Vec3& in, double (&out)[3]) {
  std::copy(in.begin(), in.end(), out);
}
void copy3(const double (&in)[3], Vec3& out) {
  std::copy(std::begin(in), std::end(in), out.begin());
}

void to_lcm(const RejectCounts& in, rigid_lcm::RejectCounts& out) {
  out.non_finite = in.non_finite;
  out.unknown_body = in.unknown_body;
  out.over_limit = in.over_limit;
  out.undecodable = in.undecodable;
  out.stale_sequence = in.stale_sequence;
  out.queue_full = in.queue_full;
  out.invalid = in.invalid;
  out.over_share = in.over_share;
  out.rate_limited = in.rate_limited;
  out.not_permitted = in.not_permitted;
}

void from_lcm(const rigid_lcm::RejectCounts& in, RejectCounts& out) {
  out.non_finite = in.non_finite;
  out.unknown_body = in.unknown_body;
  out.over_limit = in.over_limit;
  out.undecodable = in.undecodable;
  out.stale_sequence = in.stale_sequence;
  out.queue_full = in.queue_full;
  out.invalid = in.invalid;
  out.over_share = in.over_share;
  out.rate_limited = in.rate_limited;
  out.not_permitted = in.not_permitted;
}

void to_lcm(const TransportCounts& in, rigid_lcm::TransportCounts& out) {
  out.sent = in.sent;
  out.send_failures = in.send_failures;
  out.received = in.received;
  out.decode_failures = in.decode_failures;
}

void from_lcm(const rigid_lcm::TransportCounts& in, TransportCounts& out) {
  out.sent = in.sent;
  out.send_failures = in.send_failures;
  out.received = in.received;
  out.decode_failures = in.decode_failures;
}

}  // namespace

bool to_lcm(const StateFrame& in, rigid_lcm::WorldState& out) {
  const std::size_t n = in.body_count();
  if (!in.lengths_agree() || n > kMaxBodies) return false;
  out.num_bodies = count(n);
  out.num_xyz = count(3 * n);
  out.num_wxyz = count(4 * n);
  out.tick = in.tick;
  out.sim_time = in.sim_time;
  out.stamp_ns = in.stamp_ns;
  out.ids.assign(in.ids.begin(), in.ids.end());
  out.position.assign(in.position.begin(), in.position.end());
  out.orientation.assign(in.orientation.begin(), in.orientation.end());
  out.linear_velocity.assign(in.linear_velocity.begin(), in.linear_velocity.end());
  out.angular_velocity.assign(in.angular_velocity.begin(), in.angular_velocity.end());
  return true;
}

DecodeStatus from_lcm(const rigid_lcm::WorldState& in, StateFrame& out) {
  const auto n = static_cast<std::size_t>(in.num_bodies);
  if (static_cast<std::size_t>(in.num_xyz) != 3 * n ||
      static_cast<std::size_t>(in.num_wxyz) != 4 * n) {
    return DecodeStatus::kInconsistentLengths;
  }
  out.tick = in.tick;
  out.sim_time = in.sim_time;
  out.stamp_ns = in.stamp_ns;
  copy_prefix(in.ids, n, out.ids);
  copy_prefix(in.position, 3 * n, out.position);
  copy_prefix(in.orientation, 4 * n, out.orientation);
  copy_prefix(in.linear_velocity, 3 * n, out.linear_velocity);
  copy_prefix(in.angular_velocity, 3 * n, out.angular_velocity);
  return DecodeStatus::kOk;
}

bool to_lcm(const WrenchCommand& in, rigid_lcm::Wrench& out) {
  out.source = in.source;
  out.seq = in.seq;
  out.key = in.key;
  out.body_id = in.body_id;
  out.body_name = in.body_name;
  copy3(in.force, out.force);
  copy3(in.point, out.point);
  out.force_frame = static_cast<std::int32_t>(in.force_frame);
  copy3(in.torque, out.torque);
  out.torque_frame = static_cast<std::int32_t>(in.torque_frame);
  out.ttl = in.ttl;
  out.stamp_ns = in.stamp_ns;
  return true;
}

DecodeStatus from_lcm(const rigid_lcm::Wrench& in, WrenchCommand& out) {
  out.source = in.source;
  out.seq = in.seq;
  out.key = in.key;
  out.body_id = in.body_id;
  out.body_name = in.body_name;
  copy3(in.force, out.force);
  copy3(in.point, out.point);
  out.force_frame = static_cast<Frame>(in.force_frame);
  copy3(in.torque, out.torque);
  out.torque_frame = static_cast<Frame>(in.torque_frame);
  out.ttl = in.ttl;
  out.stamp_ns = in.stamp_ns;
  return DecodeStatus::kOk;
}

bool to_lcm(const ControlCommand& in, rigid_lcm::Control& out) {
  out.source = in.source;
  out.seq = in.seq;
  out.command = static_cast<std::int32_t>(in.command);
  out.steps = in.steps;
  out.rtf = in.rtf;
  return true;
}

DecodeStatus from_lcm(const rigid_lcm::Control& in, ControlCommand& out) {
  out.source = in.source;
  out.seq = in.seq;
  out.command = static_cast<ControlKind>(in.command);
  out.steps = in.steps;
  out.rtf = in.rtf;
  return DecodeStatus::kOk;
}

bool to_lcm(const ControlReply& in, rigid_lcm::ControlReply& out) {
  out.source = in.source;
  out.seq = in.seq;
  out.command = static_cast<std::int32_t>(in.command);
  out.outcome = static_cast<std::int32_t>(in.outcome);
  out.tick = in.tick;
  out.message = in.message;
  return true;
}

DecodeStatus from_lcm(const rigid_lcm::ControlReply& in, ControlReply& out) {
  out.source = in.source;
  out.seq = in.seq;
  out.command = static_cast<ControlKind>(in.command);
  out.outcome = static_cast<Outcome>(in.outcome);
  out.tick = in.tick;
  out.message = in.message;
  return DecodeStatus::kOk;
}

bool to_lcm(const StatsReport& in, rigid_lcm::Stats& out) {
  out.tick = in.tick;
  out.sim_time = in.sim_time;
  out.mode = static_cast<std::int32_t>(in.mode);
  out.paused = in.paused ? 1 : 0;
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
  to_lcm(in.rejected, out.rejected);
  to_lcm(in.dds, out.dds);
  to_lcm(in.lcm, out.lcm);
  const std::size_t n = in.refused_by_source.size();
  if (n > kMaxRefusedSources) return false;
  out.num_refused_sources = count(n);
  out.refused_sender.resize(n);
  out.refused_count.resize(n);
  out.refused_last_reason.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    out.refused_sender[i] = in.refused_by_source[i].sender;
    out.refused_count[i] = in.refused_by_source[i].count;
    out.refused_last_reason[i] = in.refused_by_source[i].last_reason;
  }
  return true;
}

DecodeStatus from_lcm(const rigid_lcm::Stats& in, StatsReport& out) {
  out.tick = in.tick;
  out.sim_time = in.sim_time;
  out.mode = static_cast<Mode>(in.mode);
  out.paused = in.paused != 0;
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
  from_lcm(in.rejected, out.rejected);
  from_lcm(in.dds, out.dds);
  from_lcm(in.lcm, out.lcm);
  const auto n = static_cast<std::size_t>(in.num_refused_sources);
  if (n > kMaxRefusedSources) return DecodeStatus::kInconsistentLengths;
  out.refused_by_source.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    out.refused_by_source[i].sender = in.refused_sender[i];
    out.refused_by_source[i].count = in.refused_count[i];
    out.refused_by_source[i].last_reason = in.refused_last_reason[i];
  }
  return DecodeStatus::kOk;
}

bool to_lcm(const SceneDescription& in, rigid_lcm::SceneInfo& out) {
  const std::size_t n = in.body_count();
  if (!in.lengths_agree() || n > kMaxBodies) return false;
  out.num_bodies = count(n);
  out.num_inertia = count(6 * n);
  out.num_shape_dims = count(3 * n);
  out.scene_name = in.scene_name;
  out.dt = in.dt;
  out.substeps = in.substeps;
  out.publish_every = in.publish_every;
  copy3(in.gravity, out.gravity);
  out.integrator = in.integrator;
  out.max_force = in.max_force;
  out.max_torque = in.max_torque;
  out.max_ttl = in.max_ttl;
  out.max_wrenches_per_source = in.max_wrenches_per_source;
  out.max_commands_per_second = in.max_commands_per_second;
  out.ids.assign(in.ids.begin(), in.ids.end());
  out.names.assign(in.names.begin(), in.names.end());
  out.masses.assign(in.masses.begin(), in.masses.end());
  out.inertia.assign(in.inertia.begin(), in.inertia.end());
  out.shape_kinds.resize(n);
  std::transform(in.shape_kinds.begin(), in.shape_kinds.end(), out.shape_kinds.begin(),
                 [](ShapeKind kind) { return static_cast<std::int32_t>(kind); });
  out.shape_dims.assign(in.shape_dims.begin(), in.shape_dims.end());
  return true;
}

DecodeStatus from_lcm(const rigid_lcm::SceneInfo& in, SceneDescription& out) {
  const auto n = static_cast<std::size_t>(in.num_bodies);
  if (static_cast<std::size_t>(in.num_inertia) != 6 * n ||
      static_cast<std::size_t>(in.num_shape_dims) != 3 * n) {
    return DecodeStatus::kInconsistentLengths;
  }
  out.scene_name = in.scene_name;
  out.dt = in.dt;
  out.substeps = in.substeps;
  out.publish_every = in.publish_every;
  copy3(in.gravity, out.gravity);
  out.integrator = in.integrator;
  out.max_force = in.max_force;
  out.max_torque = in.max_torque;
  out.max_ttl = in.max_ttl;
  out.max_wrenches_per_source = in.max_wrenches_per_source;
  out.max_commands_per_second = in.max_commands_per_second;
  copy_prefix(in.ids, n, out.ids);
  copy_prefix(in.names, n, out.names);
  copy_prefix(in.masses, n, out.masses);
  copy_prefix(in.inertia, 6 * n, out.inertia);
  out.shape_kinds.resize(n);
  std::transform(in.shape_kinds.begin(), in.shape_kinds.begin() + static_cast<std::ptrdiff_t>(n),
                 out.shape_kinds.begin(),
                 [](std::int32_t kind) { return static_cast<ShapeKind>(kind); });
  copy_prefix(in.shape_dims, 3 * n, out.shape_dims);
  return DecodeStatus::kOk;
}

bool to_lcm(const AcceptedCommand& in, rigid_lcm::AcceptedCommand& out) {
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

DecodeStatus from_lcm(const rigid_lcm::AcceptedCommand& in, AcceptedCommand& out) {
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

}  // namespace rigid::transport::lcm
