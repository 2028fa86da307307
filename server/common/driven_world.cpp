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

void DrivenWorld::reset() {
  world_.reset();  // also clears the applied loads
  wrenches_.clear();
  for (const int id : loaded_)
    is_loaded_[static_cast<std::size_t>(id)] = 0;
  loaded_.clear();
  tick_ = 0;
}

}  // namespace rigid::common
