// A client's conversation with rigidd on one bus, for the command-line tools and controllers: it
// keeps the newest SceneInfo, state and Stats, hands each state and accepted command to optional
// handlers, and sends control requests and wrenches so that they arrive exactly once.
//
// Exactly once: on DDS a message written before discovery has matched the server's reader is lost
// (readers that appear later do not get it), and discovery takes a moment. So a request waits
// until the server is seen (a SceneInfo or a state has arrived: its writers matched ours), is sent,
// and is re-sent with the same sequence number every second until answered. A copy that arrives
// after the first is refused by rigidd as a stale sequence, naming our own number as the last
// one: that refusal means "already accepted", and the real answer is awaited.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "common/cli.hpp"
#include "transport/transport.hpp"

namespace rigid::clients {

class Session final : public transport::Receiver {
 public:
  // `role`: kClient to talk to rigidd; kServer to stand in for it (rigid-record play).
  // Throws transport::TransportError (one line naming the bus and what to check).
  explicit Session(const BusOptions& options, transport::Role role = transport::Role::kClient);
  ~Session() override;
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  const BusOptions& options() const { return options_; }
  transport::Transport& transport() { return *transport_; }
  std::int64_t source() const { return source_; }

  // Called on the transport's thread for every state / accepted command (set before traffic
  // matters; the handler must return quickly and not call these setters). Setting a handler waits
  // for a call of the old one in progress: a handler that refers to a caller's locals is cleared
  // (set to {}) before they go away, and is never called after that.
  void on_each_state(std::function<void(const transport::StateFrame&)> handler);
  void on_each_accepted(std::function<void(const transport::AcceptedCommand&)> handler);
  void on_each_stats(std::function<void(const transport::StatsReport&)> handler);
  void on_each_scene(std::function<void(const transport::SceneDescription&)> handler);

  // Waits until the server has been seen (a SceneInfo or a state); false after `patience`.
  bool wait_server(std::chrono::milliseconds patience);
  // Waits for a SceneInfo (DDS: at once after discovery; LCM: within a second).
  std::optional<transport::SceneDescription> wait_scene(std::chrono::milliseconds patience);
  // How many different SceneInfos have arrived: it changes when a restarted rigidd runs another
  // scene, and a client that resolved bodies from the old one (their ids, their place in the
  // state) must resolve them again (wait_scene(0ms) gives the new one).
  std::uint64_t scene_generation() const;
  std::optional<transport::StatsReport> wait_stats(std::chrono::milliseconds patience);
  std::optional<transport::StateFrame> latest_state() const;

  // Sends the request (source and seq filled in) and returns its answer, or nothing after
  // `patience` (counted from the call, discovery included).
  std::optional<transport::ControlReply> request(transport::ControlCommand control,
                                                 std::chrono::milliseconds patience);
  // Sends the wrench (source and seq filled in) and returns the server's acceptance of it, or
  // nothing: refused (rigidd's reason in *refused, at once) or no answer within `patience`
  // (*refused left empty).
  std::optional<transport::AcceptedCommand> push(transport::WrenchCommand wrench,
                                                 std::chrono::milliseconds patience,
                                                 std::string* refused = nullptr);
  // Publishes once with the next seq; no wait (a controller's stream of wrenches). Refusals come
  // back as rigidd answers them (take_refusal).
  std::int64_t send(transport::WrenchCommand wrench);
  // The newest refusal of one of our wrenches since the last call (rigidd's reason in .message).
  std::optional<transport::ControlReply> take_refusal();
  // Our wrenches refused so far (as far as rigidd answered: at most a few a second).
  std::int64_t wrenches_refused() const;

  // How long to wait before sending the same request again.
  static constexpr std::chrono::milliseconds kResendPeriod{1000};

 private:
  void on_state(const transport::StateFrame& state) override;
  void on_stats(const transport::StatsReport& stats) override;
  void on_scene(const transport::SceneDescription& scene) override;
  void on_control_reply(const transport::ControlReply& reply) override;
  void on_accepted(const transport::AcceptedCommand& accepted) override;

  const BusOptions options_;
  const std::int64_t source_;
  std::int64_t seq_ = 0;
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  bool server_seen_ = false;
  std::optional<transport::SceneDescription> scene_;
  std::uint64_t scene_generation_ = 0;
  std::optional<transport::StateFrame> state_;
  std::optional<transport::StatsReport> stats_;
  std::vector<transport::ControlReply> replies_;          // ours only
  std::vector<transport::AcceptedCommand> acceptances_;   // ours only
  std::vector<transport::ControlReply> wrench_refusals_;  // ours, the newest 64
  std::optional<transport::ControlReply> last_refusal_;
  std::int64_t wrenches_refused_ = 0;
  std::mutex handler_mutex_;  // guards the handlers and is held while one runs
  std::function<void(const transport::StateFrame&)> state_handler_;
  std::function<void(const transport::AcceptedCommand&)> accepted_handler_;
  std::function<void(const transport::StatsReport&)> stats_handler_;
  std::function<void(const transport::SceneDescription&)> scene_handler_;
  std::unique_ptr<transport::Transport> transport_;  // last: its thread stops first
};

// Names for messages.
std::string_view control_name(transport::ControlKind kind);
std::string_view outcome_name(transport::Outcome outcome);

// The id of body `name_or_id` in `scene` (a name, or a number that is an id); nothing if unknown.
std::optional<std::int32_t> find_body(const transport::SceneDescription& scene,
                                      std::string_view name_or_id);
// "a, b, c": the scene's body names, for errors.
std::string body_list(const transport::SceneDescription& scene);

}  // namespace rigid::clients
