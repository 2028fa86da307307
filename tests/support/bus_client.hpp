// A test client of rigidd on one bus, built on the transport layer's client role: it records every
// state (with its arrival time), control reply, Stats, SceneInfo and tick of contact events, and
// sends wrenches and control requests with its own source id and increasing sequence numbers. Waits
// are bounded.
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

#include "transport/transport.hpp"

namespace rigid::rigidd::testing {

struct TimedState {
  rigid::StateFrame state;
  std::int64_t received_ns = 0;  // CLOCK_MONOTONIC
};

class BusClient final : public transport::Receiver {
 public:
  // Throws transport::TransportError when the bus cannot be set up (the test then fails with
  // what to run: scripts/net-setup).
  // `lcm_url`: empty for the default group and port (with a 4 MiB receive buffer).
  // `state_history`: DDS only, the unread states the client's reader keeps (rigid's default
  // 256; a test of rigidd's pacing takes more, so that its own stalls under a loaded suite are
  // not counted against rigidd).
  BusClient(rigid::Bus bus, const std::string& prefix, const std::string& lcm_url = "",
            int state_history = 256);
  ~BusClient() override;

  rigid::Bus bus() const { return bus_; }
  std::int64_t source() const { return source_; }
  std::int64_t next_seq() { return ++seq_; }

  // Fills source and the next seq, publishes; returns the seq used.
  std::int64_t send(rigid::WrenchCommand wrench);
  std::int64_t send(rigid::ControlCommand control);
  std::int64_t send(rigid::EditCommand edit);
  // Publishes exactly what it is given (source and seq included).
  void send_as_is(const rigid::WrenchCommand& wrench) { (void)transport_->publish(wrench); }

  // Sends `control` (with a fresh seq each time) every 50 ms until one of them is answered, so the
  // daemon is known to hear us (DDS discovery takes a moment; commands are not kept for readers
  // that appear later). Returns the answer, or nothing after `patience`.
  std::optional<rigid::ControlReply> handshake(rigid::ControlCommand control,
                                               std::chrono::milliseconds patience);
  // Sends once and waits for the reply to that seq (written to *seq when given).
  std::optional<rigid::ControlReply> request(rigid::ControlCommand control,
                                             std::chrono::milliseconds patience,
                                             std::int64_t* seq = nullptr);
  std::optional<rigid::ControlReply> request(rigid::EditCommand edit,
                                             std::chrono::milliseconds patience,
                                             std::int64_t* seq = nullptr);

  // Waits until pred() holds (called with the client's data locked), at most `patience`.
  bool wait(const std::function<bool()>& pred, std::chrono::milliseconds patience);

  // Copies (taken under the lock).
  std::vector<TimedState> states() const;
  std::optional<rigid::StatsReport> last_stats() const;
  std::optional<rigid::SceneDescription> scene() const;
  std::size_t state_count() const;
  std::optional<TimedState> last_state() const;
  std::vector<rigid::ContactEvents> contacts() const;

  // For wait() predicates (the lock is held there).
  const std::vector<TimedState>& states_locked() const { return states_; }
  const std::vector<rigid::ControlReply>& replies_locked() const { return replies_; }
  const std::optional<rigid::StatsReport>& stats_locked() const { return stats_; }
  const std::vector<rigid::ContactEvents>& contacts_locked() const { return contacts_; }
  const std::optional<rigid::SceneDescription>& scene_locked() const { return scene_; }

 private:
  std::optional<rigid::ControlReply> answer_to(std::int64_t seq,
                                               std::chrono::milliseconds patience);
  void on_state(const rigid::StateFrame& state) override;
  void on_stats(const rigid::StatsReport& stats) override;
  void on_scene(const rigid::SceneDescription& scene) override;
  void on_control_reply(const rigid::ControlReply& reply) override;
  void on_contacts(const rigid::ContactEvents& contacts) override;

  const rigid::Bus bus_;
  const std::int64_t source_;
  std::int64_t seq_ = 0;
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::vector<TimedState> states_;
  std::vector<rigid::ControlReply> replies_;
  std::optional<rigid::StatsReport> stats_;
  std::optional<rigid::SceneDescription> scene_;
  std::vector<rigid::ContactEvents> contacts_;
  std::unique_ptr<transport::Transport> transport_;  // last: its thread stops first
};

// A prefix no other test (or daemon) on this host uses.
std::string unique_prefix(const std::string& tag);

}  // namespace rigid::rigidd::testing
