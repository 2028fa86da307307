#include "rigid/client/bus.hpp"

namespace rigid::client {

std::string describe(const BusOptions& bus) {
  std::string text =
      bus.bus == Bus::kDds
          ? "dds domain " + std::to_string(bus.dds_domain)
          : "lcm " + (bus.lcm_url.empty() ? std::string(kDefaultLcmUrl) : bus.lcm_url);
  if (!bus.prefix.empty()) text += ", prefix " + bus.prefix;
  return text;
}

}  // namespace rigid::client
