// rigid's scene and states as Foxglove's well-known protobuf messages (msgs/foxglove/), for every
// tool that hands them to Foxglove: rigid-record export --mcap (a file) and rigid-view (live, over
// the Foxglove WebSocket protocol). One encoder, so the two show the same thing.
//
//   FrameTransforms  per body "world" -> its name: position and orientation, bit for bit
//   SceneUpdate      per body an entity in its own frame drawing its shape
//   BodyStates       (msgs/live/body_states.proto) every body's state by name, for plots
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "rigid/messages.hpp"

namespace google::protobuf {
class Descriptor;
}

namespace rigid::common::foxglove {

// The schema data Foxglove asks for with a protobuf channel (MCAP's protobuf profile, and the
// WebSocket protocol's advertise, base64): a FileDescriptorSet holding the message's file and
// every file it imports, dependencies first ("as produced by protoc --include_imports").
std::string descriptor_set(const google::protobuf::Descriptor* message);

// A SceneUpdate with one SceneEntity per body of `scene` (id and frame_id: the body's name,
// frame_locked, timestamp `time_ns`): its shape (box, sphere, cylinder; an ellipsoid as a scaled
// sphere, a capsule as a cylinder and two spheres), or for a body without a shape the uniform box
// with its principal moments (a point mass as a 5 cm sphere). With `replace_all`, a deletion of
// every earlier entity of the topic comes first (a live scene that changed: bodies that left it).
std::string scene_update(const SceneDescription& scene, std::uint64_t time_ns, bool replace_all);

// Appends a FrameTransforms of n bodies: per body "world" -> frame_names[i], translation =
// position[3i..], rotation = orientation[4i..] (w, x, y, z as rigid has them) reordered to
// Foxglove's x, y, z, w, each double written even when zero so that every bit is kept. Encoded by
// hand: a thousand bodies a state, where building the generated messages would cost more than the
// rest of the export.
void append_frame_transforms(std::string& out, const std::vector<std::string>& frame_names,
                             const double* position, const double* orientation,
                             std::uint64_t time_ns);

// Appends a rigid.msgs.BodyStates of `state` (its stamp as the timestamp), body i named
// names[i] (names.size() == state.body_count()). Encoded by hand, as above.
void append_body_states(std::string& out, const StateFrame& state,
                        const std::vector<std::string>& names);

}  // namespace rigid::common::foxglove
