#include "common/log_records.hpp"

#include <algorithm>

namespace rigid::common {
namespace {

template <class T, class Field>
void put(const std::vector<T>& in, Field* out) {
  out->Assign(in.begin(), in.end());
}

template <class T, class Field>
void get(const Field& in, std::vector<T>& out) {
  out.assign(in.begin(), in.end());
}

void put3(const rigid::Vec3& in, msgs::Vector3* out) {
  out->set_x(in[0]);
  out->set_y(in[1]);
  out->set_z(in[2]);
}

rigid::Vec3 get3(const msgs::Vector3& in) {
  return {in.x(), in.y(), in.z()};
}

msgs::Force::Frame put_frame(rigid::Frame f) {
  return f == rigid::Frame::kBody ? msgs::Force::BODY : msgs::Force::WORLD;
}

rigid::Frame get_frame(msgs::Force::Frame f) {
  return f == msgs::Force::BODY ? rigid::Frame::kBody : rigid::Frame::kWorld;
}

void put_counts(const rigid::TransportCounts& c,
                google::protobuf::RepeatedField<std::int64_t>* out) {
  out->Clear();
  for (const std::int64_t v : {c.sent, c.send_failures, c.received, c.decode_failures})
    out->Add(v);
}

rigid::TransportCounts get_counts(const google::protobuf::RepeatedField<std::int64_t>& in) {
  rigid::TransportCounts c;
  if (in.size() == 4) c = {in[0], in[1], in[2], in[3]};
  return c;
}

}  // namespace

void to_record(const rigid::StateFrame& in, std::int64_t recorded_ns, msgs::StateRecord& out) {
  out.set_tick(in.tick);
  out.set_sim_time(in.sim_time);
  out.set_stamp_ns(in.stamp_ns);
  put(in.ids, out.mutable_ids());
  put(in.position, out.mutable_position());
  put(in.orientation, out.mutable_orientation());
  put(in.linear_velocity, out.mutable_linear_velocity());
  put(in.angular_velocity, out.mutable_angular_velocity());
  out.set_recorded_ns(recorded_ns);
}

bool from_record(const msgs::StateRecord& in, rigid::StateFrame& out) {
  out.tick = in.tick();
  out.sim_time = in.sim_time();
  out.stamp_ns = in.stamp_ns();
  get(in.ids(), out.ids);
  get(in.position(), out.position);
  get(in.orientation(), out.orientation);
  get(in.linear_velocity(), out.linear_velocity);
  get(in.angular_velocity(), out.angular_velocity);
  return out.lengths_agree();
}

void to_record(const rigid::SceneDescription& in, std::int64_t recorded_ns,
               msgs::SceneRecord& out) {
  out.set_scene_name(in.scene_name);
  out.set_dt(in.dt);
  out.set_substeps(in.substeps);
  out.set_publish_every(in.publish_every);
  put3(in.gravity, out.mutable_gravity());
  out.set_integrator(in.integrator);
  out.set_max_force(in.max_force);
  out.set_max_torque(in.max_torque);
  out.set_max_ttl(in.max_ttl);
  out.set_max_wrenches_per_source(in.max_wrenches_per_source);
  out.set_max_commands_per_second(in.max_commands_per_second);
  put(in.ids, out.mutable_ids());
  out.mutable_names()->Assign(in.names.begin(), in.names.end());
  put(in.masses, out.mutable_masses());
  put(in.inertia, out.mutable_inertia());
  out.clear_shape_kinds();
  for (const rigid::ShapeKind k : in.shape_kinds)
    out.add_shape_kinds(static_cast<std::int32_t>(k));
  put(in.shape_dims, out.mutable_shape_dims());
  out.mutable_part_names()->Assign(in.part_names.begin(), in.part_names.end());
  out.clear_part_kinds();
  for (const rigid::ShapeKind k : in.part_kinds)
    out.add_part_kinds(static_cast<std::int32_t>(k));
  put(in.part_position, out.mutable_part_position());
  put(in.part_orientation, out.mutable_part_orientation());
  put(in.part_dims, out.mutable_part_dims());
  put(in.part_restitution, out.mutable_part_restitution());
  put(in.part_friction, out.mutable_part_friction());
  out.set_recorded_ns(recorded_ns);
}

bool from_record(const msgs::SceneRecord& in, rigid::SceneDescription& out) {
  out.scene_name = in.scene_name();
  out.dt = in.dt();
  out.substeps = in.substeps();
  out.publish_every = in.publish_every();
  out.gravity = get3(in.gravity());
  out.integrator = in.integrator();
  out.max_force = in.max_force();
  out.max_torque = in.max_torque();
  out.max_ttl = in.max_ttl();
  out.max_wrenches_per_source = in.max_wrenches_per_source();
  out.max_commands_per_second = in.max_commands_per_second();
  get(in.ids(), out.ids);
  out.names.assign(in.names().begin(), in.names().end());
  get(in.masses(), out.masses);
  get(in.inertia(), out.inertia);
  out.shape_kinds.resize(static_cast<std::size_t>(in.shape_kinds_size()));
  std::transform(in.shape_kinds().begin(), in.shape_kinds().end(), out.shape_kinds.begin(),
                 [](std::int32_t k) { return static_cast<rigid::ShapeKind>(k); });
  get(in.shape_dims(), out.shape_dims);
  out.part_names.assign(in.part_names().begin(), in.part_names().end());
  out.part_kinds.resize(static_cast<std::size_t>(in.part_kinds_size()));
  std::transform(in.part_kinds().begin(), in.part_kinds().end(), out.part_kinds.begin(),
                 [](std::int32_t k) { return static_cast<rigid::ShapeKind>(k); });
  get(in.part_position(), out.part_position);
  get(in.part_orientation(), out.part_orientation);
  get(in.part_dims(), out.part_dims);
  get(in.part_restitution(), out.part_restitution);
  get(in.part_friction(), out.part_friction);
  return out.lengths_agree();
}

void to_record(const rigid::StatsReport& in, std::int64_t recorded_ns, msgs::StatsRecord& out) {
  out.set_tick(in.tick);
  out.set_sim_time(in.sim_time);
  out.set_mode(static_cast<std::int32_t>(in.mode));
  out.set_paused(in.paused);
  out.set_rtf_last_second(in.rtf_last_second);
  out.set_rtf_since_start(in.rtf_since_start);
  out.set_lateness_p50_us(in.lateness_p50_us);
  out.set_lateness_p99_us(in.lateness_p99_us);
  out.set_lateness_max_us(in.lateness_max_us);
  out.set_overruns(in.overruns);
  out.set_step_cost_p50_us(in.step_cost_p50_us);
  out.set_step_cost_max_us(in.step_cost_max_us);
  out.set_bodies_frozen(in.bodies_frozen);
  out.set_large_rotation_steps(in.large_rotation_steps);
  out.set_states_skipped(in.states_skipped);
  out.set_commands_accepted(in.commands_accepted);
  out.set_rejected_non_finite(in.rejected.non_finite);
  out.set_rejected_unknown_body(in.rejected.unknown_body);
  out.set_rejected_over_limit(in.rejected.over_limit);
  out.set_rejected_undecodable(in.rejected.undecodable);
  out.set_rejected_stale_sequence(in.rejected.stale_sequence);
  out.set_rejected_queue_full(in.rejected.queue_full);
  out.set_rejected_invalid(in.rejected.invalid);
  out.set_rejected_over_share(in.rejected.over_share);
  out.set_rejected_rate_limited(in.rejected.rate_limited);
  out.set_rejected_not_permitted(in.rejected.not_permitted);
  put_counts(in.dds, out.mutable_dds());
  put_counts(in.lcm, out.mutable_lcm());
  out.set_recorded_ns(recorded_ns);
}

void from_record(const msgs::StatsRecord& in, rigid::StatsReport& out) {
  out.tick = in.tick();
  out.sim_time = in.sim_time();
  out.mode = static_cast<rigid::Mode>(in.mode());
  out.paused = in.paused();
  out.rtf_last_second = in.rtf_last_second();
  out.rtf_since_start = in.rtf_since_start();
  out.lateness_p50_us = in.lateness_p50_us();
  out.lateness_p99_us = in.lateness_p99_us();
  out.lateness_max_us = in.lateness_max_us();
  out.overruns = in.overruns();
  out.step_cost_p50_us = in.step_cost_p50_us();
  out.step_cost_max_us = in.step_cost_max_us();
  out.bodies_frozen = in.bodies_frozen();
  out.large_rotation_steps = in.large_rotation_steps();
  out.states_skipped = in.states_skipped();
  out.commands_accepted = in.commands_accepted();
  out.rejected = {in.rejected_non_finite(),     in.rejected_unknown_body(),
                  in.rejected_over_limit(),     in.rejected_undecodable(),
                  in.rejected_stale_sequence(), in.rejected_queue_full(),
                  in.rejected_invalid(),        in.rejected_over_share(),
                  in.rejected_rate_limited(),   in.rejected_not_permitted()};
  out.dds = get_counts(in.dds());
  out.lcm = get_counts(in.lcm());
}

void to_record(const rigid::AcceptedCommand& in, std::int64_t recorded_ns,
               msgs::CommandRecord& out) {
  out.set_tick(in.tick);
  out.set_kind(in.kind == rigid::AcceptedKind::kControl ? msgs::CommandRecord::CONTROL
               : in.kind == rigid::AcceptedKind::kEdit  ? msgs::CommandRecord::EDIT
                                                        : msgs::CommandRecord::WRENCH);
  out.set_source(in.source);
  out.set_seq(in.seq);
  out.set_key(in.key);
  out.set_body_id(in.body_id);
  put3(in.force, out.mutable_force());
  put3(in.point, out.mutable_point());
  out.set_force_frame(put_frame(in.force_frame));
  put3(in.torque, out.mutable_torque());
  out.set_torque_frame(put_frame(in.torque_frame));
  out.set_ttl(in.ttl);
  out.set_command(static_cast<std::int32_t>(in.command));
  out.set_steps(in.steps);
  out.set_rtf(in.rtf);
  out.set_stamp_ns(in.stamp_ns);
  out.set_recorded_ns(recorded_ns);
  // The edit's fields only on an edit's record: a wrench's or a control's stays as it was.
  out.clear_position();
  out.clear_orientation();
  out.clear_linear_velocity();
  out.clear_angular_velocity();
  if (in.kind != rigid::AcceptedKind::kEdit) {
    out.set_edit(0);
    out.set_set(0);
    out.set_velocity_frame(msgs::Force::WORLD);
    out.set_angular_velocity_frame(msgs::Force::WORLD);
    return;
  }
  out.set_edit(static_cast<std::int32_t>(in.edit));
  out.set_set(in.set);
  put3(in.position, out.mutable_position());
  msgs::Quaternion* q = out.mutable_orientation();
  q->set_w(in.orientation[0]);
  q->set_x(in.orientation[1]);
  q->set_y(in.orientation[2]);
  q->set_z(in.orientation[3]);
  put3(in.linear_velocity, out.mutable_linear_velocity());
  out.set_velocity_frame(put_frame(in.velocity_frame));
  put3(in.angular_velocity, out.mutable_angular_velocity());
  out.set_angular_velocity_frame(put_frame(in.angular_velocity_frame));
}

void from_record(const msgs::CommandRecord& in, rigid::AcceptedCommand& out) {
  out.tick = in.tick();
  out.kind = in.kind() == msgs::CommandRecord::CONTROL ? rigid::AcceptedKind::kControl
             : in.kind() == msgs::CommandRecord::EDIT  ? rigid::AcceptedKind::kEdit
                                                       : rigid::AcceptedKind::kWrench;
  out.source = in.source();
  out.seq = in.seq();
  out.key = in.key();
  out.body_id = in.body_id();
  out.force = get3(in.force());
  out.point = get3(in.point());
  out.force_frame = get_frame(in.force_frame());
  out.torque = get3(in.torque());
  out.torque_frame = get_frame(in.torque_frame());
  out.ttl = in.ttl();
  out.command = static_cast<rigid::ControlKind>(in.command());
  out.steps = in.steps();
  out.rtf = in.rtf();
  out.stamp_ns = in.stamp_ns();
  out.edit = static_cast<rigid::EditKind>(in.edit());
  out.set = in.set();
  out.position = get3(in.position());
  // A record without an orientation (a wrench's, a control's) reads as the plain default.
  if (in.has_orientation()) {
    const msgs::Quaternion& q = in.orientation();
    out.orientation = {q.w(), q.x(), q.y(), q.z()};
  } else {
    out.orientation = rigid::StateEdit{}.orientation;
  }
  out.linear_velocity = get3(in.linear_velocity());
  out.velocity_frame = get_frame(in.velocity_frame());
  out.angular_velocity = get3(in.angular_velocity());
  out.angular_velocity_frame = get_frame(in.angular_velocity_frame());
}

void to_record(const rigid::ContactEvents& in, std::int64_t recorded_ns, msgs::ContactRecord& out) {
  out.set_tick(in.tick);
  out.set_sim_time(in.sim_time);
  out.set_stamp_ns(in.stamp_ns);
  out.set_dropped(in.dropped);
  out.clear_kinds();
  for (const rigid::ContactKind k : in.kinds)
    out.add_kinds(static_cast<std::int32_t>(k));
  put(in.bodies, out.mutable_bodies());
  put(in.parts, out.mutable_parts());
  put(in.times, out.mutable_times());
  put(in.position, out.mutable_position());
  put(in.normal, out.mutable_normal());
  put(in.impulse, out.mutable_impulse());
  out.set_recorded_ns(recorded_ns);
}

bool from_record(const msgs::ContactRecord& in, rigid::ContactEvents& out) {
  out.tick = in.tick();
  out.sim_time = in.sim_time();
  out.stamp_ns = in.stamp_ns();
  out.dropped = in.dropped();
  out.kinds.resize(static_cast<std::size_t>(in.kinds_size()));
  std::transform(in.kinds().begin(), in.kinds().end(), out.kinds.begin(),
                 [](std::int32_t k) { return static_cast<rigid::ContactKind>(k); });
  get(in.bodies(), out.bodies);
  get(in.parts(), out.parts);
  get(in.times(), out.times);
  get(in.position(), out.position);
  get(in.normal(), out.normal);
  get(in.impulse(), out.impulse);
  return out.lengths_agree() && out.event_count() <= rigid::kMaxContactEvents;
}

}  // namespace rigid::common
