// Which bus a client talks to rigidd on, and where on it: the options every rigid tool takes
// (--transport, --prefix, --dds-domain, --lcm-url, --security), as a value.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>

#include "rigid/messages.hpp"

namespace rigid::client {

// LCM's default URL for rigid: ttl=0 multicast, which never leaves the host.
inline constexpr std::string_view kDefaultLcmUrl = "udpm://239.255.76.67:7667?ttl=0";

struct BusOptions {
  Bus bus = Bus::kDds;
  std::string prefix;  // the prefix rigidd runs with: letters, digits and '_' only
  std::uint32_t dds_domain = 0;
  std::string lcm_url;   // empty: kDefaultLcmUrl (with a receive buffer for large states)
  std::string security;  // a DDS Security identity directory (rigid-keys add); empty: none
};

// "dds domain 0" or "lcm udpm://...", plus ", prefix P" when there is one: for messages.
std::string describe(const BusOptions& bus);

// The bus could not be set up: one line naming the bus, the resource and what to check (for
// instance the multicast route LCM needs, or a DDS Security identity that does not load).
class BusError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace rigid::client
