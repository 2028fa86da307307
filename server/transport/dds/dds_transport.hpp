// The Cyclone DDS transport: one participant, one topic per rigid message, writers and readers by
// role, and a receive thread waiting on the readers. Configuration (network interface, peers) comes
// from CYCLONEDDS_URI; config/cyclonedds.xml is the loopback one (scripts/net-setup prints it).
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "transport/transport.hpp"

namespace rigid::transport::dds {

struct Options {
  Role role = Role::kServer;
  std::uint32_t domain = 0;
  std::string prefix;           // see topic.hpp; letters, digits and '_' only
  bool reliable_state = false;  // rigid/state reliable instead of best-effort keep-last 1
};

// Throws TransportError (one line: what failed and what to check) when DDS cannot be set up.
// `receiver` is called from the transport's thread from before this returns until the transport is
// destroyed, and must outlive it.
std::unique_ptr<Transport> make_transport(const Options& options, Receiver& receiver);

}  // namespace rigid::transport::dds
