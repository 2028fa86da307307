// visualization_msgs/msg/MarkerArray of a scene's bodies, for rviz2 and Foxglove: each body's
// shape in its own frame (frame_id = the body's name, which /tf moves; frame_locked so that a
// viewer keeps following the frame), sized from the scene's dimensions and coloured as rigid-view
// colours it (its palette, by the body's place in the scene).
//
// Shapes: sphere -> SPHERE (scale 2r), ellipsoid -> SPHERE (scale 2a, 2b, 2c), box -> CUBE
// (scale = the side lengths), cylinder -> CYLINDER (2r, 2r, length; axis z as in rigid), capsule
// -> a CYLINDER and two SPHERE ends in namespace "rigid_capsule_ends" (rviz2 has no capsule), a
// body without a shape (a point mass) -> a sphere of kPointMarkerDiameter. Marker layout as in
// ROS 2 Humble and later (Marker.msg with texture, uv_coordinates and mesh_file).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "rigid/messages.hpp"
#include "transport/ros/ros_face.hpp"

namespace rigid::transport::ros {

inline constexpr double kPointMarkerDiameter = 0.1;  // m

// A plane is drawn as a square of this side (m) and kPlaneMarkerThickness, its top face on the
// plane (an infinite plane has no size of its own).
inline constexpr double kPlaneMarkerSide = 20.0;
inline constexpr double kPlaneMarkerThickness = 0.002;

// The serialized MarkerArray (action ADD): the bodies in namespace "rigid" (id = the body's id),
// the static parts in "rigid_static" (id = their place in `statics`, each in its own frame),
// a capsule's ends in "rigid_capsule_ends" (bodies) or "rigid_static_capsule_ends".
void encode_markers(const SceneDescription& scene, std::span<const StaticFrame> statics,
                    std::vector<std::uint8_t>& out);

}  // namespace rigid::transport::ros
