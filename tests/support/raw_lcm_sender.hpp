// Sends an arbitrary payload on an LCM channel, as LCM's UDP multicast provider frames a small
// message (magic "LC02", sequence number, channel, payload), without the LCM library: a way to put
// bytes on the bus that no encoder would produce (the undecodable-payload test).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace rigid::rigidd::testing {

// To the default group 239.255.76.67:7667 with TTL 0 (this host only). false if the socket
// could not send.
bool send_raw_lcm(const std::string& channel, const std::vector<std::uint8_t>& payload);

}  // namespace rigid::rigidd::testing
