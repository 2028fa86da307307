#include "transport/lcm/lcm_command_socket.hpp"

#include <arpa/inet.h>
#include <linux/filter.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <limits>
#include <system_error>

namespace rigid::transport::lcm {
namespace {

// The udpm framing of liblcm 1.3.1 (lcm/udpm_util.h, lcm/lcm_udpm.c), all integers big-endian:
//   short message: u32 magic "LC02", u32 seqno, channel, NUL, payload
//   fragment:      u32 magic "LC03", u32 seqno, u32 payload size of the whole message,
//                  u32 offset of this fragment's data, u16 fragment number, u16 fragment count;
//                  fragment 0 carries channel, NUL before its data.
// liblcm fragments when channel + NUL + payload exceed 65499 bytes (1435 on macOS).
constexpr std::uint32_t kMagicShort = 0x4c433032;
constexpr std::uint32_t kMagicFragment = 0x4c433033;
constexpr std::size_t kShortHeaderBytes = 8;
constexpr std::size_t kFragmentHeaderBytes = 20;
constexpr std::size_t kFragmentNumberOffset = 16;
constexpr std::size_t kMaxChannelLength = 63;  // LCM_MAX_CHANNEL_NAME_LENGTH

constexpr std::string_view kScheme = "udpm://";
constexpr std::string_view kDefaultNetwork = "239.255.76.67:7667";  // liblcm's, for "udpm://"

std::uint32_t read_u32(const std::uint8_t* bytes) {
  return (std::uint32_t{bytes[0]} << 24) | (std::uint32_t{bytes[1]} << 16) |
         (std::uint32_t{bytes[2]} << 8) | std::uint32_t{bytes[3]};
}

std::uint16_t read_u16(const std::uint8_t* bytes) {
  return static_cast<std::uint16_t>((bytes[0] << 8) | bytes[1]);
}

// The NUL-terminated channel name at the start of `bytes`, or nothing when no NUL comes within
// LCM's longest name (or the datagram's end). `found` says which.
std::string_view channel_at(std::span<const std::uint8_t> bytes, bool& found) {
  const std::size_t limit = std::min(bytes.size(), kMaxChannelLength + 1);
  const auto* nul = static_cast<const std::uint8_t*>(std::memchr(bytes.data(), 0, limit));
  found = nul != nullptr;
  if (!found) return {};
  return {reinterpret_cast<const char*>(bytes.data()),
          static_cast<std::size_t>(nul - bytes.data())};
}

// The socket's filter, run by the kernel on each datagram before it is queued (classic BPF,
// Documentation/networking/filter.rst; on a UDP socket offset 0 is the UDP header's first byte
// and the length counts its 8 bytes): every fragment but a message's first is dropped there.
// Everything sent to the group reaches this socket, rigidd's own states included: at 10^5 bodies
// a state is 10.8 MB in 166 fragments, which the command thread would read all of (a CPU share
// worth filtering out: bench/notes/transport.md) and whose burst would share the socket's receive
// buffer with commands, where it could crowd one out.
// The first fragment still comes through: it names the channel, and one on a command channel is
// reported as a command too large to be one. Datagrams too short for a fragment header pass whole
// (read and counted as malformed).
constexpr std::uint32_t kUdpHeaderBytes = 8;
constexpr std::array<sock_filter, 8> kFragmentFilter{{
    BPF_STMT(BPF_LD | BPF_W | BPF_LEN, 0),  // A = datagram length
    BPF_JUMP(BPF_JMP | BPF_JGE | BPF_K, kUdpHeaderBytes + kFragmentHeaderBytes, 0, 4),
    BPF_STMT(BPF_LD | BPF_W | BPF_ABS, kUdpHeaderBytes),  // A = magic (loads are big-endian)
    BPF_JUMP(BPF_JMP | BPF_JEQ | BPF_K, kMagicFragment, 0, 2),
    BPF_STMT(BPF_LD | BPF_H | BPF_ABS, kUdpHeaderBytes + kFragmentNumberOffset),
    BPF_JUMP(BPF_JMP | BPF_JEQ | BPF_K, 0, 0, 1),  // the first fragment: kept
    BPF_STMT(BPF_RET | BPF_K, 0xffffffffU),        // keep it whole
    BPF_STMT(BPF_RET | BPF_K, 0),                  // drop it
}};

[[noreturn]] void refuse_url(std::string_view url, std::string_view why) {
  throw TransportError("LCM: cannot receive commands on '" + std::string(url) +
                       "': " + std::string(why));
}

// A whole-string decimal number in [low, high].
template <class Int>
bool parse_decimal(std::string_view text, Int low, Int high, Int& out) {
  Int value{};
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, value);
  if (text.empty() || ec != std::errc{} || ptr != end || value < low || value > high) return false;
  out = value;
  return true;
}

}  // namespace

std::string_view to_string(Rejection rejection) {
  switch (rejection) {
    case Rejection::kTooShort:
      return "shorter than an LCM header";
    case Rejection::kBadMagic:
      return "not an LCM datagram (bad magic)";
    case Rejection::kBadChannel:
      return "channel name not NUL-terminated within 63 characters";
    case Rejection::kFragment:
      return "fragment of a message too large for one datagram";
  }
  return "unknown";
}

UdpmEndpoint parse_udpm_url(std::string_view url) {
  if (!url.starts_with(kScheme)) refuse_url(url, "not a udpm:// URL");
  std::string_view rest = url.substr(kScheme.size());
  const std::size_t query = rest.find('?');
  std::string_view network = rest.substr(0, query);
  std::string_view options = query == std::string_view::npos ? "" : rest.substr(query + 1);
  if (network.empty()) network = kDefaultNetwork;

  UdpmEndpoint endpoint;
  const std::size_t colon = network.find(':');
  if (colon == std::string_view::npos) refuse_url(url, "no port after the group address");
  const std::string_view address = network.substr(0, colon);
  std::array<char, INET_ADDRSTRLEN> address_z{};
  in_addr group{};
  if (address.size() >= address_z.size()) refuse_url(url, "bad group address");
  std::copy(address.begin(), address.end(), address_z.begin());
  if (::inet_pton(AF_INET, address_z.data(), &group) != 1) refuse_url(url, "bad group address");
  endpoint.group = ntohl(group.s_addr);
  if ((endpoint.group & 0xf0000000U) != 0xe0000000U) {
    refuse_url(url, "the group address is not IPv4 multicast (224.0.0.0/4)");
  }
  if (!parse_decimal<std::uint16_t>(network.substr(colon + 1), 1, 65535, endpoint.port)) {
    refuse_url(url, "bad port (a decimal number in 1..65535)");
  }

  // liblcm splits the options on '?' as well as '&'.
  while (!options.empty()) {
    const std::size_t end = std::min(options.find('&'), options.find('?'));
    const std::string_view option = options.substr(0, end);
    options = end == std::string_view::npos ? "" : options.substr(end + 1);
    const std::size_t equals = option.find('=');
    if (option.substr(0, equals) != "recv_buf_size") continue;
    const std::string_view value =
        equals == std::string_view::npos ? std::string_view{} : option.substr(equals + 1);
    if (!parse_decimal<int>(value, 0, std::numeric_limits<int>::max(), endpoint.recv_buf_size)) {
      refuse_url(url, "bad recv_buf_size (a decimal number of bytes)");
    }
  }
  return endpoint;
}

CommandSocket::CommandSocket(std::string_view url, std::vector<std::string> channels)
    : endpoint_(parse_udpm_url(url)),
      channels_(std::move(channels)),
      buffer_(std::make_unique_for_overwrite<std::uint8_t[]>(kBufferBytes)) {
  for (const std::string& channel : channels_) {
    if (channel.size() > kMaxChannelLength) {
      refuse_url(url, "channel '" + channel + "' is longer than LCM's 63 characters");
    }
  }

  fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd_ < 0) refuse_url(url, std::string("socket: ") + std::strerror(errno));
  // The destructor does not run for a constructor that throws.
  const auto fail = [&](std::string_view what, std::string_view hint = {}) {
    const int error = errno;
    ::close(fd_);
    fd_ = -1;
    refuse_url(url, std::string(what) + ": " + std::strerror(error) + std::string(hint));
  };

  // liblcm 1.3.1 sets SO_REUSEADDR, and SO_REUSEPORT only on macOS and FreeBSD. On Linux,
  // SO_REUSEADDR on every socket bound to the port is what lets them share it.
  const int on = 1;
  if (::setsockopt(fd_, SOL_SOCKET, SO_REUSEADDR, &on, sizeof on) < 0) fail("SO_REUSEADDR");
  if (endpoint_.recv_buf_size > 0 &&
      ::setsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &endpoint_.recv_buf_size,
                   sizeof endpoint_.recv_buf_size) < 0) {
    fail("SO_RCVBUF");
  }

  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(endpoint_.group);
  address.sin_port = htons(endpoint_.port);
  if (::bind(fd_, reinterpret_cast<const sockaddr*>(&address), sizeof address) < 0) fail("bind");

  // Linux has had socket filters since 2.2; without one the socket only reads more.
  const sock_fprog program{static_cast<unsigned short>(kFragmentFilter.size()),
                           const_cast<sock_filter*>(kFragmentFilter.data())};
  filtered_ = ::setsockopt(fd_, SOL_SOCKET, SO_ATTACH_FILTER, &program, sizeof program) == 0;

  // As liblcm: the kernel picks the interface from the route to the group.
  ip_mreq membership{};
  membership.imr_multiaddr.s_addr = htonl(endpoint_.group);
  membership.imr_interface.s_addr = htonl(INADDR_ANY);
  if (::setsockopt(fd_, IPPROTO_IP, IP_ADD_MEMBERSHIP, &membership, sizeof membership) < 0) {
    fail("joining the multicast group",
         " (udpm on this host needs a multicast route on lo: run scripts/net-setup as root, or "
         "'ip route replace 224.0.0.0/4 dev lo')");
  }
}

CommandSocket::~CommandSocket() {
  if (fd_ >= 0) ::close(fd_);
}

int CommandSocket::receive_buffer_bytes() const {
  int bytes = 0;
  socklen_t size = sizeof bytes;
  if (::getsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &bytes, &size) < 0) return 0;
  return bytes;
}

CommandSocketCounts CommandSocket::counts() const {
  CommandSocketCounts counts;
  counts.datagrams = datagrams_.load(std::memory_order_relaxed);
  counts.delivered = delivered_.load(std::memory_order_relaxed);
  counts.other_channel = other_channel_.load(std::memory_order_relaxed);
  counts.fragments = fragments_.load(std::memory_order_relaxed);
  counts.malformed = malformed_.load(std::memory_order_relaxed);
  counts.errors = errors_.load(std::memory_order_relaxed);
  return counts;
}

bool CommandSocket::accepts(std::string_view channel) const {
  return std::any_of(channels_.begin(), channels_.end(),
                     [channel](const std::string& ours) { return ours == channel; });
}

CommandSocket::Datagram CommandSocket::next() {
  sockaddr_in from{};
  socklen_t from_size = sizeof from;
  ssize_t received = 0;
  do {
    from_size = sizeof from;
    received = ::recvfrom(fd_, buffer_.get(), kBufferBytes, 0, reinterpret_cast<sockaddr*>(&from),
                          &from_size);
  } while (received < 0 && errno == EINTR);
  if (received < 0) {
    if (errno != EAGAIN && errno != EWOULDBLOCK) errors_.fetch_add(1, std::memory_order_relaxed);
    return {};
  }
  datagrams_.fetch_add(1, std::memory_order_relaxed);

  Datagram datagram;
  datagram.bytes = static_cast<std::size_t>(received);
  datagram.session = make_session(ntohl(from.sin_addr.s_addr), ntohs(from.sin_port));
  const std::span<const std::uint8_t> bytes(buffer_.get(), datagram.bytes);

  const auto malformed = [&](Rejection reason) {
    malformed_.fetch_add(1, std::memory_order_relaxed);
    datagram.kind = Kind::kRejected;
    datagram.reason = reason;
    return datagram;
  };

  // liblcm discards anything shorter than a short header, whatever its magic.
  if (bytes.size() < kShortHeaderBytes) return malformed(Rejection::kTooShort);
  const std::uint32_t magic = read_u32(bytes.data());

  if (magic == kMagicShort) {
    bool terminated = false;
    const std::span<const std::uint8_t> body = bytes.subspan(kShortHeaderBytes);
    const std::string_view channel = channel_at(body, terminated);
    if (!terminated) return malformed(Rejection::kBadChannel);
    if (!accepts(channel)) {
      other_channel_.fetch_add(1, std::memory_order_relaxed);
      datagram.kind = Kind::kIgnored;
      return datagram;
    }
    delivered_.fetch_add(1, std::memory_order_relaxed);
    datagram.kind = Kind::kMessage;
    datagram.channel = channel;
    datagram.payload = body.subspan(channel.size() + 1);
    return datagram;
  }

  if (magic == kMagicFragment) {
    if (bytes.size() < kFragmentHeaderBytes) return malformed(Rejection::kTooShort);
    // Dropped unread: the sizes and offsets it announces are never looked at.
    fragments_.fetch_add(1, std::memory_order_relaxed);
    datagram.kind = Kind::kIgnored;
    if (read_u16(bytes.data() + kFragmentNumberOffset) == 0) {
      bool terminated = false;
      const std::string_view channel = channel_at(bytes.subspan(kFragmentHeaderBytes), terminated);
      if (terminated && accepts(channel)) {
        datagram.kind = Kind::kRejected;
        datagram.reason = Rejection::kFragment;
        datagram.channel = channel;
      }
    }
    return datagram;
  }

  return malformed(Rejection::kBadMagic);
}

}  // namespace rigid::transport::lcm
