// One bus, seen from the server or from a client: publish messages, receive decoded ones.
// The DDS and LCM adapters (dds/dds_transport.hpp, lcm/lcm_transport.hpp) implement it; the rest of
// the program sees only this and messages.hpp.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>

#include "rigid/messages.hpp"
#include "transport/decode_status.hpp"

namespace rigid::transport {

// Which end of the conversation a transport is. The server publishes state, stats, scene, contact
// events, accepted commands and control replies and receives wrenches and controls; a client does
// the opposite.
enum class Role : std::uint8_t { kServer, kClient };

// Who sent a command, as far as its bus can tell. Only valid during the callback.
struct Origin {
  // The sending endpoint: on DDS the writer's instance handle (one per client transport), on LCM
  // the sender's UDP address and port (one per lcm_t). A restarted client is a new session.
  std::uint64_t session = 0;
  // With DDS Security: the authenticated identity that wrote the command, taken from the writer's
  // partition (push/IDENTITY/BODY, control/IDENTITY: controls and edits), which access control
  // lets only that identity use. Empty without security.
  std::string_view identity;
  // With DDS Security, for a wrench: the one body its writer's partition permits. Empty otherwise.
  std::string_view permitted_body;
  bool authenticated = false;  // identity is set (DDS Security)
};

// Called on the transport's receive thread (one per transport), one message at a time. The message
// is only valid during the call: the transport reuses its storage for the next one, so that
// receiving allocates nothing once the buffers have grown. A receiver shared by two transports is
// called from two threads. Callbacks must return quickly (push into a queue, do not step physics).
class Receiver {
 public:
  virtual ~Receiver() = default;
  // Server role.
  virtual void on_wrench(const WrenchCommand& /*wrench*/, const Origin& /*origin*/) {}
  virtual void on_control(const ControlCommand& /*control*/, const Origin& /*origin*/) {}
  virtual void on_edit(const EditCommand& /*edit*/, const Origin& /*origin*/) {}
  // Client role.
  virtual void on_state(const StateFrame& /*state*/) {}
  virtual void on_stats(const StatsReport& /*stats*/) {}
  virtual void on_scene(const SceneDescription& /*scene*/) {}
  virtual void on_control_reply(const ControlReply& /*reply*/) {}
  virtual void on_accepted(const AcceptedCommand& /*accepted*/) {}
  virtual void on_contacts(const ContactEvents& /*contacts*/) {}
  // Either role: a payload that did not decode. Never fatal; count it.
  virtual void on_decode_error(const DecodeError& /*error*/) {}
};

enum class PublishResult : std::uint8_t {
  kOk = 0,
  kWrongRole,     // this transport's role does not publish that message
  kInvalid,       // the message's per-body arrays disagree with its body count
  kFailed,        // the bus refused it (counted in counts().send_failures)
  kNotPermitted,  // DDS Security: this identity's permissions do not allow it (that body, control)
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
  // Not pure either, for the same reason.
  virtual PublishResult publish(const ContactEvents& /*contacts*/) {
    return PublishResult::kWrongRole;
  }
  // Sends the scene last published again, for subscribers that joined since: LCM has no
  // durability, so it keeps the encoded scene for this (rigidd calls it once a second). On DDS
  // the SceneInfo writer's transient-local history already gives late joiners the scene, and this
  // sends nothing. kInvalid if no scene was published.
  virtual PublishResult republish_scene() { return PublishResult::kOk; }
  // Client role.
  virtual PublishResult publish(const WrenchCommand& wrench) = 0;
  virtual PublishResult publish(const ControlCommand& control) = 0;
  // Not pure, so that a stand-in transport need not carry this topic: it then refuses.
  virtual PublishResult publish(const EditCommand& /*edit*/) { return PublishResult::kWrongRole; }

  // Messages sent and received by this transport since it started (the Stats per-bus figures).
  virtual TransportCounts counts() const = 0;
};

}  // namespace rigid::transport
