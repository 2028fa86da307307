// A transport for BusOptions, as every rigid client opens one: DDS on the loopback configuration
// unless CYCLONEDDS_URI names another, LCM with a receive buffer large enough for big states.
// Internal to the tools (rigid-record play stands in for rigidd with Role::kServer); the SDK's
// users go through Session.
#pragma once

#include <memory>

#include "rigid/client/bus.hpp"
#include "transport/transport.hpp"

namespace rigid::client {

// Throws BusError. `receiver` must outlive the transport.
std::unique_ptr<transport::Transport> connect(const BusOptions& options, transport::Role role,
                                              transport::Receiver& receiver);

}  // namespace rigid::client
