#include "common/state_conversion.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "physics/math.hpp"

namespace rigid::common {

void shape_state_frame(const physics::World& world, rigid::StateFrame& frame) {
  const auto n = static_cast<std::size_t>(world.body_count());
  frame.resize(n);
  for (std::size_t i = 0; i < n; ++i)
    frame.ids[i] = static_cast<std::int32_t>(i);
}

void fill_state_frame(const physics::World& world, std::int64_t tick, double sim_time,
                      rigid::StateFrame& frame) {
  frame.tick = tick;
  frame.sim_time = sim_time;
  world.write_states({frame.position.data(), frame.orientation.data(), frame.linear_velocity.data(),
                      frame.angular_velocity.data()});
}

rigid::ShapeKind shape_kind(physics::ShapeKind k) {
  switch (k) {
    case physics::ShapeKind::kSphere:
      return rigid::ShapeKind::kSphere;
    case physics::ShapeKind::kBox:
      return rigid::ShapeKind::kBox;
    case physics::ShapeKind::kCylinder:
      return rigid::ShapeKind::kCylinder;
    case physics::ShapeKind::kEllipsoid:
      return rigid::ShapeKind::kEllipsoid;
    case physics::ShapeKind::kCapsule:
      return rigid::ShapeKind::kCapsule;
  }
  return rigid::ShapeKind::kNone;
}

physics::Vec3 shape_dims(const physics::Shape& s) {
  switch (s.kind) {
    case physics::ShapeKind::kSphere:
      return {s.size.x(), 0.0, 0.0};
    case physics::ShapeKind::kCylinder:
    case physics::ShapeKind::kCapsule:
      return {s.size.x(), s.size.z(), 0.0};
    case physics::ShapeKind::kBox:
    case physics::ShapeKind::kEllipsoid:
      break;
  }
  return s.size;
}

rigid::ContactKind contact_kind(physics::ContactEventKind k) {
  switch (k) {
    case physics::ContactEventKind::kImpact:
      return rigid::ContactKind::kImpact;
    case physics::ContactEventKind::kResting:
      return rigid::ContactKind::kResting;
    case physics::ContactEventKind::kSliding:
      return rigid::ContactKind::kSliding;
    case physics::ContactEventKind::kRolling:
      return rigid::ContactKind::kRolling;
    case physics::ContactEventKind::kSeparate:
      break;
  }
  return rigid::ContactKind::kSeparate;
}

void reserve_contact_events(rigid::ContactEvents& out) {
  constexpr std::size_t n = rigid::kMaxContactEvents;
  out.kinds.reserve(n);
  out.bodies.reserve(n);
  out.parts.reserve(n);
  out.times.reserve(n);
  out.position.reserve(3 * n);
  out.normal.reserve(3 * n);
  out.impulse.reserve(3 * n);
}

void fill_contact_events(std::span<const physics::ContactEvent> events, std::int64_t tick,
                         double sim_time, rigid::ContactEvents& out) {
  const std::size_t n = std::min(events.size(), rigid::kMaxContactEvents);
  out.tick = tick;
  out.sim_time = sim_time;
  out.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const physics::ContactEvent& e = events[i];
    out.kinds[i] = contact_kind(e.kind);
    out.bodies[i] = e.body;
    out.parts[i] = e.part;
    out.times[i] = e.time;
    for (int k = 0; k < 3; ++k) {
      out.position[3 * i + k] = e.p_W[k];
      out.normal[3 * i + k] = e.n_W[k];
      out.impulse[3 * i + k] = e.impulse_W[k];
    }
  }
}

PlaneFrame plane_frame(const physics::PlaneSpec& plane) {
  const physics::Vec3& n = plane.n_W;
  const double w = 1.0 + n.z();
  const double norm = std::hypot(w, n.x(), n.y());
  const physics::Quat q_WS = norm < 1e-12
                                 ? physics::Quat(0.0, 1.0, 0.0, 0.0)
                                 : physics::Quat(w / norm, -n.y() / norm, n.x() / norm, 0.0);
  return {plane.offset * n, q_WS};
}

rigid::SceneDescription describe_scene(const scene::Scene& scene, const physics::World& world) {
  rigid::SceneDescription d;
  const physics::WorldSpec& spec = scene.world;
  // The path's tail if it is longer than the message allows (msgs/rigid.idl: string<256>).
  d.scene_name = scene.path.size() < rigid::kMaxMessageLength
                     ? scene.path
                     : scene.path.substr(scene.path.size() - (rigid::kMaxMessageLength - 1));
  d.dt = 1.0 / scene.rate_hz;
  d.substeps = scene.substeps;
  d.publish_every = scene.publish_every;
  d.gravity = {spec.g_W.x(), spec.g_W.y(), spec.g_W.z()};
  d.integrator = std::string(world.integrator().name);
  d.max_force = scene.limits.max_force;
  d.max_torque = scene.limits.max_torque;
  d.max_ttl = scene.limits.max_ttl;
  d.max_wrenches_per_source = scene.limits.max_wrenches_per_source;
  d.max_commands_per_second = scene.limits.max_commands_per_second;
  const std::size_t n = spec.bodies.size();
  for (std::size_t i = 0; i < n; ++i) {
    const physics::BodySpec& b = spec.bodies[i];
    d.ids.push_back(static_cast<std::int32_t>(i));
    d.names.push_back(b.name);
    d.masses.push_back(b.mass);
    const physics::Mat3 I = b.has_inertia ? b.I_B : physics::Mat3::Zero();
    d.inertia.insert(d.inertia.end(), {I(0, 0), I(1, 1), I(2, 2), I(0, 1), I(0, 2), I(1, 2)});
    const std::optional<physics::Shape>& shape =
        i < scene.shapes.size() ? scene.shapes[i] : std::optional<physics::Shape>();
    d.shape_kinds.push_back(shape ? shape_kind(shape->kind) : rigid::ShapeKind::kNone);
    const physics::Vec3 dims = shape ? shape_dims(*shape) : physics::Vec3::Zero();
    d.shape_dims.insert(d.shape_dims.end(), {dims.x(), dims.y(), dims.z()});
  }
  const auto add_part = [&d](const std::string& name, rigid::ShapeKind kind,
                             const physics::Vec3& p_WS, const physics::Quat& q_WS,
                             const physics::Vec3& dims, const physics::Surface& surface) {
    d.part_names.push_back(name);
    d.part_kinds.push_back(kind);
    d.part_position.insert(d.part_position.end(), {p_WS.x(), p_WS.y(), p_WS.z()});
    d.part_orientation.insert(d.part_orientation.end(), {q_WS.w(), q_WS.x(), q_WS.y(), q_WS.z()});
    d.part_dims.insert(d.part_dims.end(), {dims.x(), dims.y(), dims.z()});
    d.part_restitution.push_back(surface.restitution);
    d.part_friction.push_back(surface.friction);
  };
  for (const physics::PlaneSpec& p : spec.planes) {
    const PlaneFrame f = plane_frame(p);
    add_part(p.name, rigid::ShapeKind::kPlane, f.p_WS, f.q_WS, physics::Vec3::Zero(), p.surface);
  }
  for (const physics::StaticSpec& s : spec.statics)
    add_part(s.name, shape_kind(s.shape.kind), s.p_WS, s.q_WS, shape_dims(s.shape), s.surface);
  return d;
}

}  // namespace rigid::common
