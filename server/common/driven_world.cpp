#include "common/driven_world.hpp"

namespace rigid::common {
namespace {

physics::Vec3 eigen(const Vec3& v) {
  return {v[0], v[1], v[2]};
}

// The one place a message's Frame becomes the physics' own: the physics core includes nothing but
// Eigen and the standard library, so it keeps an equivalent enum of its own.
physics::Frame frame_of(rigid::Frame f) {
  return f == rigid::Frame::kBody ? physics::Frame::kBody : physics::Frame::kWorld;
}

}  // namespace

DrivenWorld::DrivenWorld(const physics::WorldSpec& spec, double tick_dt, int substeps,
                         std::size_t wrench_capacity)
    : world_(spec), tick_dt_(tick_dt), substeps_(substeps), wrenches_(wrench_capacity) {
  loaded_.reserve(static_cast<std::size_t>(world_.body_count()));
  is_loaded_.assign(static_cast<std::size_t>(world_.body_count()), 0);
}

WrenchTable::Upsert DrivenWorld::apply(const Wrench& wrench, std::uint64_t sender,
                                       std::size_t share) {
  return wrenches_.upsert(wrench, sender, share, tick_ + ticks_to_live(wrench.ttl, tick_dt_));
}

void DrivenWorld::clear_loaded() {
  for (const int id : loaded_) {
    world_.clear_applied(id);
    is_loaded_[static_cast<std::size_t>(id)] = 0;
  }
  loaded_.clear();
}

void DrivenWorld::load_wrenches() {
  // Clear the bodies loaded last time (only those), then load the acting wrenches in arrival order
  // (deterministic), remembering their bodies.
  if (wrenches_.size() == 0 && loaded_.empty()) return;
  clear_loaded();
  for (const ActiveWrench& e : wrenches_.active()) {
    const Wrench& w = e.wrench;
    world_.add_force(w.body, eigen(w.force), eigen(w.point), frame_of(w.force_frame));
    if (w.torque[0] != 0.0 || w.torque[1] != 0.0 || w.torque[2] != 0.0) {
      world_.add_torque(w.body, eigen(w.torque), frame_of(w.torque_frame));
    }
    if (!is_loaded_[static_cast<std::size_t>(w.body)]) {
      is_loaded_[static_cast<std::size_t>(w.body)] = 1;
      loaded_.push_back(w.body);  // within the capacity reserved for every body: no allocation
    }
  }
}

void DrivenWorld::step_tick() {
  load_wrenches();
  world_.step(substeps_);
  ++tick_;
  wrenches_.expire(tick_);
}

void DrivenWorld::edit(const Edit& e) {
  const int id = e.body;
  if (e.kind == rigid::EditKind::kResetBody) {
    const physics::BodySpec spec = world_.body_spec(id);
    world_.set_state(id, physics::BodyState{spec.p_WBo, spec.q_WB, spec.v_WBo, spec.w_WB});
    wrenches_.drop_body(id);
    world_.clear_applied(id);  // (the next tick's rebuild would too: loaded_ still lists it)
    return;
  }
  physics::BodyState s = world_.state(id);
  if ((e.set & rigid::kSetPosition) != 0) s.p_WBo = eigen(e.position);
  if ((e.set & rigid::kSetOrientation) != 0) {
    const auto& q = e.orientation;
    s.q_WB = physics::Quat(q[0], q[1], q[2], q[3]).normalized();
  }
  // B after the edit: R_WB maps a velocity expressed in B to W.
  const physics::Quat& q_WB = s.q_WB;
  if ((e.set & rigid::kSetLinearVelocity) != 0) {
    const physics::Vec3 v = eigen(e.linear_velocity);
    s.v_WBo = e.velocity_frame == rigid::Frame::kBody ? physics::Vec3(q_WB * v) : v;
  }
  if ((e.set & rigid::kSetAngularVelocity) != 0) {
    const physics::Vec3 w = eigen(e.angular_velocity);
    s.w_WB = e.angular_velocity_frame == rigid::Frame::kBody ? physics::Vec3(q_WB * w) : w;
  }
  world_.set_state(id, s);
}

void DrivenWorld::reset() {
  world_.reset();  // also clears the applied loads
  wrenches_.clear();
  for (const int id : loaded_)
    is_loaded_[static_cast<std::size_t>(id)] = 0;
  loaded_.clear();
  tick_ = 0;
}

}  // namespace rigid::common
