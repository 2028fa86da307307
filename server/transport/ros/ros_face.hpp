// rigidd --ros: ROS 2's face of the DDS transport, on the transport's own participant. rigidd then
// is a ROS 2 node ("rigidd" in `ros2 node list`) that publishes, from the same states as
// rigid/state:
//
//   /tf            tf2_msgs/msg/TFMessage: world -> each body, at every state (reliable,
//                  volatile, depth 100: tf2's QoS), stamped with the state's simulated time
//   /tf_static     the scene's static parts: planes and fixed shapes (transient local, depth 1)
//   /clock         rosgraph_msgs/msg/Clock: simulated time, at every state (always "/clock":
//                  where use_sim_time looks, whatever the namespace)
//   rigid/markers  visualization_msgs/msg/MarkerArray: the bodies' and static parts' shapes
//                  (transient local)
//
// and takes geometry_msgs/msg/WrenchStamped on rigid/BODY/wrench (one topic per body, frame_id
// "world" or the body's name: the frame the wrench is expressed in; it acts at the centre of mass)
// and serves the simulation_interfaces services under the node (~/get_simulator_features, ...:
// ros/sim_server.hpp). Names are relative to --ros-namespace.
//
// Commands go to the transport's Receiver like rigid's own: the same limits, sequence handling,
// shares, refusal counting, --controls and DDS Security permissions.
#pragma once

#include <array>
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "rigid/messages.hpp"
#include "transport/ros/ros_messages.hpp"

namespace rigid::transport::dds {
class ParticipantAddOn;
}

namespace rigid::transport::ros {

// A static part of the scene (a plane or a fixed shape), published once on /tf_static as
// world -> name and drawn among the markers. A plane's frame has its origin on the plane, nearest
// the world's origin, and its z axis along the plane's normal.
struct StaticFrame {
  std::string name;
  Vec3 p_WS{};
  std::array<double, 4> q_WS_wxyz{1.0, 0.0, 0.0, 0.0};
  bool plane = false;
  ShapeKind shape = ShapeKind::kNone;  // a fixed shape's, with dims as SceneInfo's shape_dims
  Vec3 dims{};
};

struct Options {
  std::string ns;  // "" or "/a/b" (normalize_namespace)
  Distro distro = Distro::kJazzy;
  std::string node_name = "rigidd";
  std::string world_frame = "world";
  std::vector<std::string> body_names;  // by id
  std::vector<StaticFrame> static_frames;
  // How long a ROS wrench acts at most when not replaced (s of simulated time): the scene's
  // limits.max_ttl. A WrenchStamped carries no lifetime; it holds until the same publisher's next
  // one on that body, like a zero-order hold.
  double wrench_ttl = 60.0;
  rigid::Mode mode = rigid::Mode::kRealtime;
  // DDS Security is on: a command's origin is the writer's participant, and the topic it came on
  // (which access control lets only permitted identities write) says what it may do.
  bool secure = false;
};

// What --ros will offer for these options, for rigidd's start line.
struct Plan {
  std::size_t wrench_topics = 0;
  std::vector<std::string> notes;  // bodies left without a wrench topic or a usable frame, and why
  std::size_t largest_sample = 0;  // bytes: the largest sample the face sends (markers, /tf)
};
Plan plan(const Options& options);

std::shared_ptr<dds::ParticipantAddOn> make_face(const Options& options);

}  // namespace rigid::transport::ros
