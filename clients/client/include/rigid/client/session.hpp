// A client's conversation with rigidd on one bus: it keeps the newest SceneInfo, state and Stats,
// hands each state, accepted command, Stats and scene to optional handlers, and sends control
// requests, edits and wrenches so that they arrive exactly once.
//
// Exactly once: on DDS a message written before discovery has matched the server's reader is lost
// (readers that appear later do not get it), and discovery takes a moment. So a request waits
// until the server is seen (a SceneInfo or a state has arrived: its writers matched ours), is sent,
// and is re-sent with the same sequence number every second until answered. A copy that arrives
// after the first is refused by rigidd as a stale sequence, naming our own number as the last
// one: that refusal means "already accepted", and the real answer is awaited.
//
// With CYCLONEDDS_URI unset, DDS uses rigid's loopback configuration (the installed
// share/rigid/cyclonedds.xml, else the source tree's), so a client finds a local rigidd from any
// shell.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "rigid/client/bus.hpp"
#include "rigid/messages.hpp"

namespace rigid::client {

class Session {
 public:
  // Joins the bus. Throws BusError (one line naming the bus and what to check).
  explicit Session(const BusOptions& options = {});
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  const BusOptions& options() const;
  // This session's source id (random, positive): rigidd keeps sequence numbers per source.
  std::int64_t source() const;

  // Called on the bus's receive thread for every state / accepted command / Stats / SceneInfo /
  // ContactEvents
  // (set before traffic matters; the handler must return quickly and not call these setters).
  // Setting a handler waits for a call of the old one in progress: a handler that refers to a
  // caller's locals is cleared (set to {}) before they go away, and is never called after that.
  void on_each_state(std::function<void(const StateFrame&)> handler);
  // The same state as one immutable shared frame, for a handler that keeps states beyond the call
  // (no copy of its own on the receive thread); called before on_each_state's handler.
  void on_each_state_shared(std::function<void(const std::shared_ptr<const StateFrame>&)> handler);
  void on_each_accepted(std::function<void(const AcceptedCommand&)> handler);
  void on_each_stats(std::function<void(const StatsReport&)> handler);
  void on_each_scene(std::function<void(const SceneDescription&)> handler);
  // Each tick's contact events (a scene with static parts: rigid/contacts), in tick order; every
  // tick that had any, none repeated.
  void on_each_contacts(std::function<void(const ContactEvents&)> handler);

  // Waits until the server has been seen (a SceneInfo or a state); false after `patience`.
  bool wait_server(std::chrono::milliseconds patience);
  // Waits for a SceneInfo (DDS: at once after discovery; LCM: within a second).
  std::optional<SceneDescription> wait_scene(std::chrono::milliseconds patience);
  // How many different SceneInfos have arrived: it changes when a restarted rigidd runs another
  // scene, and a client that resolved bodies from the old one (their ids, their place in the
  // state) must resolve them again (wait_scene(0ms) gives the new one).
  std::uint64_t scene_generation() const;
  std::optional<StatsReport> wait_stats(std::chrono::milliseconds patience);
  std::optional<StateFrame> latest_state() const;
  // The newest state without copying it (shared and immutable; null before the first).
  std::shared_ptr<const StateFrame> latest_state_shared() const;

  // Sends the request (source and seq filled in) and returns its answer, or nothing after
  // `patience` (counted from the call, discovery included).
  std::optional<ControlReply> request(ControlCommand control, std::chrono::milliseconds patience);
  // The control requests by name (rigidctl pause, resume, step N, reset, rate X). step(n) is
  // answered when its n ticks are done; every state they publish has been sent by then.
  std::optional<ControlReply> pause(std::chrono::milliseconds patience);
  std::optional<ControlReply> resume(std::chrono::milliseconds patience);
  std::optional<ControlReply> step(std::int64_t ticks, std::chrono::milliseconds patience);
  std::optional<ControlReply> reset(std::chrono::milliseconds patience);
  std::optional<ControlReply> set_rtf(double rtf, std::chrono::milliseconds patience);

  // Edits of the running world, answered like a control (ControlReply.command kReplyToEdit, the
  // tick T it was made at: the state of tick T + 1 is the first stepped from it; a paused rigidd
  // publishes the edited state at once, as tick T). edit() sends any (source, seq and, if 0,
  // stamp_ns filled in); a body is named by id (or body_id < 0 and body_name).
  std::optional<ControlReply> edit(EditCommand edit, std::chrono::milliseconds patience);
  // The parts of the body's state that state.set names (kSetPosition | ...), in their frames.
  std::optional<ControlReply> set_state(std::int32_t body, const StateEdit& state,
                                        std::chrono::milliseconds patience);
  // The body back to its scene state, the wrenches acting on it dropped.
  std::optional<ControlReply> reset_body(std::int32_t body, std::chrono::milliseconds patience);

  // Sends the wrench (source and seq filled in) and returns the server's acceptance of it, or
  // nothing: refused (rigidd's reason in *refused, at once) or no answer within `patience`
  // (*refused left empty).
  std::optional<AcceptedCommand> push(WrenchCommand wrench, std::chrono::milliseconds patience,
                                      std::string* refused = nullptr);
  // Publishes once with the next seq (returned); no wait (a controller's stream of wrenches).
  // Refusals come back as rigidd answers them (take_refusal).
  std::int64_t send(WrenchCommand wrench);
  // The newest refusal of one of our wrenches since the last call (rigidd's reason in .message).
  std::optional<ControlReply> take_refusal();
  // Our wrenches refused so far (as far as rigidd answered: at most a few a second).
  std::int64_t wrenches_refused() const;

  // How long to wait before sending the same request again.
  static constexpr std::chrono::milliseconds kResendPeriod{1000};

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rigid::client
