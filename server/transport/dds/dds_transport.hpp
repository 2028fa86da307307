// The Cyclone DDS transport: one participant, one topic per rigid message, writers and readers by
// role, and a receive thread waiting on the readers. Configuration (network interface, peers) comes
// from CYCLONEDDS_URI; config/cyclonedds.xml is the loopback one (scripts/net-setup prints it).
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "transport/transport.hpp"

namespace rigid::transport::dds {

class ParticipantAddOn;  // participant_add_on.hpp

inline constexpr int kDefaultStateHistory = 256;
inline constexpr int kMaxStateHistory = 65536;

struct Options {
  Role role = Role::kServer;
  std::uint32_t domain = 0;
  std::string prefix;           // see topic.hpp; letters, digits and '_' only
  bool reliable_state = false;  // rigid/state reliable instead of best-effort keep-last 1
  // DDS Security: an identity directory (rigid-keys add KEYSTORE NAME makes
  // KEYSTORE/identities/NAME). Empty: plain DDS, which trusts every process that reaches it.
  std::string security;
  // A client's state reader keeps this many unread states (dds_qos.hpp says why more than one).
  int state_history = kDefaultStateHistory;
};

// "DDS on loopback unless a network is configured": when CYCLONEDDS_URI is unset, points it at
// the project's loopback configuration (the installed one, else the source tree's) and returns
// what the process now uses, for its start line: "CYCLONEDDS_URI=... (interfaces: lo)".
std::string ensure_dds_config();

// Makes Cyclone drop any sample larger than `bytes` as its first fragment arrives, in both
// directions (Internal/MaxSampleSize, added to CYCLONEDDS_URI): rigidd sets it from the largest
// sample it publishes, so that an attacker's 100 MB sample is never reassembled in its memory.
void limit_sample_size(std::size_t bytes);

// Throws TransportError (one line: what failed and what to check) when DDS cannot be set up.
// `receiver` is called from the transport's thread from before this returns until the transport is
// destroyed, and must outlive it.
std::unique_ptr<Transport> make_transport(const Options& options, Receiver& receiver);
// The same with another face on its participant (server role: rigidd --ros, ros/ros_face.hpp),
// told of everything the transport publishes, its readers drained by the transport's receive
// thread.
std::unique_ptr<Transport> make_transport(const Options& options, Receiver& receiver,
                                          std::shared_ptr<ParticipantAddOn> add_on);

}  // namespace rigid::transport::dds
