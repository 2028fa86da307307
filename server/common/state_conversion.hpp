// Physics -> wire: the world's state as a rigid::StateFrame, and the scene as a
// SceneDescription. It lives here, not in transport/, so that the transport layer knows nothing
// of the physics. Body ids on the wire are the physics ids (0 .. n-1, in scene order).
#pragma once

#include <cstdint>
#include <span>

#include "physics/world.hpp"
#include "rigid/messages.hpp"
#include "scene/scene.hpp"

namespace rigid::common {

// Sizes `frame` for the world and writes the ids: once, at start-up.
void shape_state_frame(const physics::World& world, rigid::StateFrame& frame);

// Writes tick, sim_time and every body's state into a frame shaped by shape_state_frame.
// Allocates nothing. stamp_ns is left for the hand-over to the buses (SharedStates).
void fill_state_frame(const physics::World& world, std::int64_t tick, double sim_time,
                      rigid::StateFrame& frame);

// The contact events of one tick (World::contact_events after the tick's steps) as the
// ContactEvents message of `tick` (sim_time: its end). `out` is resized to the events (at most
// rigid::kMaxContactEvents, which the World never exceeds; more are cut off): allocation-free once
// its capacity holds them (reserve_contact_events). stamp_ns and dropped are left as they are.
void fill_contact_events(std::span<const physics::ContactEvent> events, std::int64_t tick,
                         double sim_time, rigid::ContactEvents& out);
// Room in `out` for a full tick of events, so that filling it never allocates.
void reserve_contact_events(rigid::ContactEvents& out);
rigid::ContactKind contact_kind(physics::ContactEventKind k);

// A physics shape on the wire: its kind, and its dims: sphere (radius, 0, 0); cylinder and capsule
// (radius, length, 0); box and ellipsoid as given (the scene's size already matches).
rigid::ShapeKind shape_kind(physics::ShapeKind k);
physics::Vec3 shape_dims(const physics::Shape& s);

// A plane's frame S, in which it is the plane z = 0, solid below: S's origin is the plane's point
// nearest W's origin, its z axis the plane's unit normal n, turned from W's z by the shortest
// rotation ((1 + n_z, -n_y, n_x, 0) normalised; a half turn about x for n = -z). SceneInfo, and
// the ROS face's /tf_static, carry a plane as this frame.
struct PlaneFrame {
  physics::Vec3 p_WS;
  physics::Quat q_WS;
};
PlaneFrame plane_frame(const physics::PlaneSpec& plane);

// The scene as the SceneInfo message: ids, names, masses, inertia tensors in B (zero for a point
// mass) and shapes (SHAPE_NONE when the file gave the inertia directly), the static parts (planes,
// then static shapes: name, kind, pose, dims, material), the tick period and the integrator the
// world runs.
rigid::SceneDescription describe_scene(const scene::Scene& scene, const physics::World& world);

}  // namespace rigid::common
