// The simulation_interfaces services of rigidd --ros (ros/sim_services.hpp): a request reader and
// a reply writer per service, named and framed as rmw_cyclonedds does, so that any ROS 2 client
// (rclpy, rclcpp, `ros2 service call`) and any tool written for a simulator's standard services
// drives rigidd.
//
// Pause, play, stop, step and reset become rigid control requests, sent to the transport's
// Receiver like rigid's own (the same --controls, permissions, rate shares and refusal counting)
// and answered when the loop answers them. Questions (features, state, entities) are answered at
// once from the latest state, within a per-client budget so that no client can keep the receive
// thread busy. A reply waits until the client's reply reader is matched (rmw_cyclonedds pairs a
// client's endpoints by the "clientid" in their user data), at most a second.
#pragma once

#include <dds/dds.h>

#include <array>
#include <cstdint>
#include <mutex>
#include <string>
#include <unordered_map>
#include <vector>

#include "rigid/messages.hpp"
#include "transport/dds/dds_entity.hpp"
#include "transport/ros/raw_sertype.hpp"
#include "transport/ros/sim_services.hpp"
#include "transport/traffic_counter.hpp"
#include "transport/transport.hpp"

namespace rigid::transport::ros {

class SimServer {
 public:
  struct Setup {
    std::string node_fq_name;  // "/rigidd" or "/ns/rigidd": services are NODE/get_..., ...
    std::string world_frame;
    std::vector<std::string> body_names;  // by id
    rigid::Mode mode = rigid::Mode::kRealtime;
    bool secure = false;
    std::string service_id;  // "serviceid" user data of the endpoints
  };

  // Creates every service's endpoints; the read conditions come from conditions().
  SimServer(dds_entity_t participant, Setup setup, Receiver& receiver, TrafficCounter& counter);
  SimServer(const SimServer&) = delete;
  SimServer& operator=(const SimServer&) = delete;

  // Request readers, then reply writers' match conditions (for replies waiting on a match).
  std::vector<dds_entity_t> conditions() const;
  void on_triggered(std::size_t index);  // receive thread
  std::vector<dds_entity_t> readers() const;
  std::vector<dds_entity_t> writers() const;

  // Publisher threads.
  void on_state(const StateFrame& state);
  void on_accepted(const AcceptedCommand& accepted);
  bool on_control_reply(const ControlReply& reply);

  // Deletes the endpoints (the transport's receive thread has ended).
  void close();

 private:
  struct Endpoints {
    SimService kind{};
    RawTopic request_topic;
    RawTopic reply_topic;
    dds::Entity reader;
    dds::Entity writer;
    dds::Entity read_condition;
    dds::Entity matched_condition;
  };
  // A request waiting for the loop's answer to its control(s).
  struct Pending {
    bool used = false;
    SimService kind{};
    std::size_t service = 0;
    RequestHeader header;
    std::string client_id;  // the client's "clientid", empty if it has none
    std::int64_t first_seq = 0;
    int count = 0;
    int remaining = 0;
    SimResult ok_result = SimResult::kOk;  // what success answers (ALREADY_IN_TARGET_STATE)
    // What success makes of the simulation state (SetSimulationState, StepSimulation).
    ControlKind last_kind = ControlKind::kNone;
    bool stopping = false;  // SetSimulationState STOPPED
    bool failed = false;
    std::string message;
    std::int64_t since_ns = 0;
  };
  // A reply that waits for the client's reader to be matched.
  struct Deferred {
    std::size_t service = 0;
    std::string client_id;
    std::vector<std::uint8_t> bytes;
    std::int64_t give_up_ns = 0;
  };

  void on_request(std::size_t service, std::span<const std::uint8_t> bytes,
                  const dds_sample_info_t& info);
  void answer(std::size_t service, const SimRequest& request, const dds_sample_info_t& info,
              const std::string& client_id);
  // Sends `controls` (kinds, with steps for kStep) for a request, or answers at once if they
  // cannot be queued.
  void send_controls(std::size_t service, SimService kind, const SimRequest& request,
                     const dds_sample_info_t& info, const std::string& client_id,
                     std::initializer_list<ControlKind> controls, std::int64_t steps,
                     SimResult ok_result, bool stopping);
  // Sends the reply now if the client's reader is matched, else keeps it for a second.
  void reply(std::size_t service, const std::string& client_id, std::vector<std::uint8_t>& bytes);
  bool client_matched(std::size_t service, const std::string& client_id) const;
  void retry_deferred();
  std::string client_id_of(std::size_t service, dds_instance_handle_t writer);
  bool take_budget(dds_instance_handle_t writer, double cost);
  Origin origin_of(std::size_t service, dds_instance_handle_t writer);
  static std::int64_t now_ns();

  Setup setup_;
  Receiver& receiver_;
  TrafficCounter& counter_;
  std::vector<Endpoints> services_;
  std::unordered_map<std::string_view, std::int32_t> body_index_;  // views into setup_.body_names

  // Receive thread only.
  SimRequest request_;
  std::vector<std::uint8_t> scratch_;
  std::unordered_map<dds_instance_handle_t, std::string> client_ids_;
  struct Budget {
    double tokens = 0.0;
    std::int64_t last_ns = 0;
  };
  std::unordered_map<dds_instance_handle_t, Budget> budgets_;
  std::unordered_map<dds_instance_handle_t, std::string> identities_;

  // Shared between the receive thread and the publisher threads.
  std::mutex mutex_;
  std::int64_t source_ = 0;  // the source of every control this server sends
  std::int64_t seq_ = 0;
  std::array<Pending, 64> pending_;
  std::vector<Deferred> deferred_;
  bool paused_ = false;
  bool stopped_ = false;
  std::vector<std::uint8_t> reply_scratch_;  // publisher threads, under mutex_
  // The latest state (publisher thread), for GetEntityState (receive thread).
  std::mutex latest_mutex_;
  StateFrame latest_;
  bool have_latest_ = false;
};

}  // namespace rigid::transport::ros
