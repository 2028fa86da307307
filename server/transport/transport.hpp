// One bus, seen from the server or from a client: publish messages, receive decoded ones.
// The DDS and LCM adapters (dds/dds_transport.hpp, lcm/lcm_transport.hpp) implement it; the rest of
// the program sees only this and messages.hpp.
#pragma once

#include <stdexcept>
#include <string>

#include "transport/decode_status.hpp"
#include "transport/messages.hpp"

namespace rigid::transport {

// Which end of the conversation a transport is. The server publishes state, stats, scene and
// control replies and receives wrenches and controls; a client does the opposite.
enum class Role : std::uint8_t { kServer, kClient };

// Called on the transport's receive thread (one per transport), one message at a time. The message
// is only valid during the call: the transport reuses its storage for the next one, so that
// receiving allocates nothing once the buffers have grown. A receiver shared by two transports is
// called from two threads. Callbacks must return quickly (push into a queue, do not step physics).
class Receiver {
 public:
  virtual ~Receiver() = default;
  // Server role.
  virtual void on_wrench(const WrenchCommand& /*wrench*/) {}
  virtual void on_control(const ControlCommand& /*control*/) {}
  // Client role.
  virtual void on_state(const StateFrame& /*state*/) {}
  virtual void on_stats(const StatsReport& /*stats*/) {}
  virtual void on_scene(const SceneDescription& /*scene*/) {}
  virtual void on_control_reply(const ControlReply& /*reply*/) {}
  virtual void on_accepted(const AcceptedCommand& /*accepted*/) {}
  // Either role: a payload that did not decode. Never fatal; count it.
  virtual void on_decode_error(const DecodeError& /*error*/) {}
};

enum class PublishResult : std::uint8_t {
  kOk = 0,
  kWrongRole,  // this transport's role does not publish that message
  kInvalid,    // the message's per-body arrays disagree with its body count
  kFailed,     // the bus refused it (counted in counts().send_failures)
};

// Setting a transport up failed: the message is one line naming the bus, the resource and what to
// check (for instance the multicast route LCM needs).
class TransportError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Publishing is thread-safe; each message type has its own writer, buffers and lock, so publishing
// one type never waits for another. A best-effort topic (state, by default) never waits for a slow
// subscriber; a reliable one may wait a few milliseconds for acknowledgements, then fails.
class Transport {
 public:
  virtual ~Transport() = default;

  virtual Bus bus() const = 0;
  virtual Role role() const = 0;

  // Server role.
  virtual PublishResult publish(const StateFrame& state) = 0;
  virtual PublishResult publish(const StatsReport& stats) = 0;
  virtual PublishResult publish(const SceneDescription& scene) = 0;
  virtual PublishResult publish(const ControlReply& reply) = 0;
  // Not pure, so that a stand-in transport (a test's) need not carry this topic: it then refuses.
  virtual PublishResult publish(const AcceptedCommand& /*accepted*/) {
    return PublishResult::kWrongRole;
  }
  // Client role.
  virtual PublishResult publish(const WrenchCommand& wrench) = 0;
  virtual PublishResult publish(const ControlCommand& control) = 0;

  // Messages sent and received by this transport since it started (the Stats per-bus figures).
  virtual TransportCounts counts() const = 0;
};

}  // namespace rigid::transport
