// The LCM transport: one lcm_t, a channel per rigid message, subscriptions by role and a receive
// thread. The default URL keeps traffic on this host; LCM needs a multicast route on the loopback
// interface for it (scripts/net-setup adds it).
#pragma once

#include <memory>
#include <string>
#include <string_view>

#include "transport/transport.hpp"

namespace rigid::transport::lcm {

// ttl=0: multicast that never leaves the host. Add "&recv_buf_size=4194304" on a subscriber of
// large states (above ~200 KB), or the kernel drops them silently.
inline constexpr std::string_view kDefaultUrl = "udpm://239.255.76.67:7667?ttl=0";

struct Options {
  Role role = Role::kServer;
  std::string url{kDefaultUrl};
  std::string prefix;  // see topic.hpp; letters, digits and '_' only
};

// Throws TransportError (one line: what failed and what to check) when LCM cannot be set up.
// `receiver` is called from the transport's thread from before this returns until the transport is
// destroyed, and must outlive it.
std::unique_ptr<Transport> make_transport(const Options& options, Receiver& receiver);

}  // namespace rigid::transport::lcm
