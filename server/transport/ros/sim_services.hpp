// The simulator-agnostic ROS 2 services of simulation_interfaces (ros-simulation/
// simulation_interfaces 2.x, the ones Gazebo implements) that rigidd serves: their names, types,
// requests and responses in ROS 2's CDR layout.
//
// On DDS a ROS 2 service is two topics, "rq<name>Request" and "rr<name>Reply", whose samples
// start with a request header that rmw_cyclonedds writes before the message: the client's 64-bit
// id (its request writer's instance handle) and a 64-bit sequence number, both in the sample's
// byte order. A server echoes both in its reply; the client keeps the replies with its own id.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "rigid/messages.hpp"
#include "transport/decode_status.hpp"
#include "transport/ros/ros_messages.hpp"

namespace rigid::transport::ros {

enum class SimService : std::uint8_t {
  kGetSimulatorFeatures,
  kGetSimulationState,
  kSetSimulationState,
  kStepSimulation,
  kResetSimulation,
  kGetEntityState,
  kSetEntityState,
  kGetEntities,
};

struct SimServiceInfo {
  SimService kind;
  std::string_view name;  // the service's name under the node ("get_simulator_features")
  std::string_view type;  // its type ("GetSimulatorFeatures")
};

inline constexpr std::array<SimServiceInfo, 8> kSimServices{{
    {SimService::kGetSimulatorFeatures, "get_simulator_features", "GetSimulatorFeatures"},
    {SimService::kGetSimulationState, "get_simulation_state", "GetSimulationState"},
    {SimService::kSetSimulationState, "set_simulation_state", "SetSimulationState"},
    {SimService::kStepSimulation, "step_simulation", "StepSimulation"},
    {SimService::kResetSimulation, "reset_simulation", "ResetSimulation"},
    {SimService::kGetEntityState, "get_entity_state", "GetEntityState"},
    {SimService::kSetEntityState, "set_entity_state", "SetEntityState"},
    {SimService::kGetEntities, "get_entities", "GetEntities"},
}};

// simulation_interfaces/msg/Result.result.
enum class SimResult : std::uint8_t {
  kFeatureUnsupported = 0,
  kOk = 1,
  kNotFound = 2,
  kIncorrectState = 3,
  kOperationFailed = 4,
  kAlreadyInTargetState = 101,  // SetSimulationState
};

// simulation_interfaces/msg/SimulationState.state.
enum class SimState : std::uint8_t {
  kStopped = 0,
  kPlaying = 1,
  kPaused = 2,
  kQuitting = 3,
};

// simulation_interfaces/msg/SimulatorFeatures values.
namespace feature {
inline constexpr std::uint16_t kEntityStateGetting = 10;
inline constexpr std::uint16_t kSimulationReset = 20;
inline constexpr std::uint16_t kSimulationResetSpawned = 23;
inline constexpr std::uint16_t kSimulationStateGetting = 24;
inline constexpr std::uint16_t kSimulationStateSetting = 25;
inline constexpr std::uint16_t kSimulationStatePause = 26;
inline constexpr std::uint16_t kStepSimulationSingle = 31;
inline constexpr std::uint16_t kStepSimulationMultiple = 32;
}  // namespace feature

// ResetSimulation.scope bits.
inline constexpr std::uint8_t kScopeTime = 1;
inline constexpr std::uint8_t kScopeState = 2;
inline constexpr std::uint8_t kScopeSpawned = 4;
inline constexpr std::uint8_t kScopeAll = 255;

struct RequestHeader {
  std::uint64_t client = 0;
  std::int64_t seq = 0;
};

// Longest entity name and name filter accepted (a body's name is at most kMaxNameLength).
inline constexpr std::size_t kMaxEntityLength = 256;

// What a request asks, as far as rigidd answers it.
struct SimRequest {
  RequestHeader header;
  std::uint8_t state = 0;   // SetSimulationState
  std::uint64_t steps = 0;  // StepSimulation
  std::uint8_t scope = 0;   // ResetSimulation
  std::string entity;       // GetEntityState, SetEntityState
  std::string filter;       // GetEntities: the name filter (POSIX extended regular expression)
  // GetEntities: a category, tag or bounds filter (rigid has none of these features).
  bool other_filters = false;
};

DecodeStatus decode_request(SimService kind, std::span<const std::uint8_t> bytes, SimRequest& out);

// simulation_interfaces/msg/EntityState: header (stamp, frame_id), pose, twist, acceleration (zero:
// rigid does not report accelerations).
struct EntityState {
  RosTime stamp;
  std::string frame_id;
  Vec3 position{};
  std::array<double, 4> orientation_wxyz{1.0, 0.0, 0.0, 0.0};
  Vec3 linear_velocity{};
  Vec3 angular_velocity{};
};

void encode_features_response(const RequestHeader& h, std::span<const std::uint16_t> features,
                              std::string_view custom_info, std::vector<std::uint8_t>& out);
// SetSimulationState, StepSimulation, ResetSimulation, SetEntityState: a Result alone.
void encode_result_response(const RequestHeader& h, SimResult result, std::string_view message,
                            std::vector<std::uint8_t>& out);
void encode_simulation_state_response(const RequestHeader& h, SimState state, SimResult result,
                                      std::string_view message, std::vector<std::uint8_t>& out);
void encode_entity_state_response(const RequestHeader& h, SimResult result,
                                  std::string_view message, const EntityState& state,
                                  std::vector<std::uint8_t>& out);
void encode_entities_response(const RequestHeader& h, SimResult result, std::string_view message,
                              std::span<const std::string_view> entities,
                              std::vector<std::uint8_t>& out);

}  // namespace rigid::transport::ros
