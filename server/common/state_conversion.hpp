// Physics -> wire: the world's state as a rigid::StateFrame, and the scene as a
// SceneDescription. It lives here, not in transport/, so that the transport layer knows nothing
// of the physics. Body ids on the wire are the physics ids (0 .. n-1, in scene order).
#pragma once

#include <cstdint>

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

// A physics shape on the wire: its kind, and its dims: sphere (radius, 0, 0); cylinder and capsule
// (radius, length, 0); box and ellipsoid as given (the scene's size already matches).
rigid::ShapeKind shape_kind(physics::ShapeKind k);
physics::Vec3 shape_dims(const physics::Shape& s);

// The scene as the SceneInfo message: ids, names, masses, inertia tensors in B (zero for a point
// mass) and shapes (SHAPE_NONE when the file gave the inertia directly), the static parts (planes,
// then static shapes: name, kind, pose, dims, material), the tick period and the integrator the
// world runs.
rigid::SceneDescription describe_scene(const scene::Scene& scene, const physics::World& world);

}  // namespace rigid::common
