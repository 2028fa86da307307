#include "raw_lcm_sender.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

namespace rigid::rigidd::testing {
namespace {

void put_be32(std::vector<std::uint8_t>& out, std::uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8)
    out.push_back(static_cast<std::uint8_t>(v >> shift));
}

}  // namespace

bool send_raw_lcm(const std::string& channel, const std::vector<std::uint8_t>& payload) {
  const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
  if (fd < 0) return false;
  const unsigned char ttl = 0;
  ::setsockopt(fd, IPPROTO_IP, IP_MULTICAST_TTL, &ttl, sizeof ttl);
  std::vector<std::uint8_t> datagram;
  put_be32(datagram, 0x4c433032);  // "LC02": a message in one datagram
  put_be32(datagram, 0);           // sequence number
  datagram.insert(datagram.end(), channel.begin(), channel.end());
  datagram.push_back(0);
  datagram.insert(datagram.end(), payload.begin(), payload.end());
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(7667);
  ::inet_pton(AF_INET, "239.255.76.67", &to.sin_addr);
  const ssize_t sent = ::sendto(fd, datagram.data(), datagram.size(), 0,
                                reinterpret_cast<const sockaddr*>(&to), sizeof to);
  ::close(fd);
  return sent == static_cast<ssize_t>(datagram.size());
}

}  // namespace rigid::rigidd::testing
