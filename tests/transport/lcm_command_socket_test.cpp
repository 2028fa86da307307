// CommandSocket against liblcm's own udpm publisher and against hand-made datagrams, over loopback.
// Needs the multicast route scripts/net-setup adds (224.0.0.0/4 dev lo). Each test uses its own
// port so that none sees another's traffic; every wait is bounded by poll timeouts.
#include "transport/lcm/lcm_command_socket.hpp"

#include <arpa/inet.h>
#include <dirent.h>
#include <gtest/gtest.h>
#include <lcm/lcm.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <functional>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "allocation_counter.hpp"

namespace rigid::transport::lcm {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;
using Bytes = std::vector<std::uint8_t>;

constexpr const char* kGroup = "239.255.76.67";
const std::vector<std::string> kChannels{"RIGID_WRENCH", "RIGID_CONTROL"};

// A 4 MB receive buffer: a fragmented 200 KB message must not overflow the default one.
std::string url(int port) {
  return "udpm://" + std::string(kGroup) + ":" + std::to_string(port) +
         "?ttl=0&recv_buf_size=4194304";
}

struct LcmDeleter {
  void operator()(lcm_t* lcm) const { lcm_destroy(lcm); }
};
using Lcm = std::unique_ptr<lcm_t, LcmDeleter>;

// The AF_INET datagram sockets of this process, by descriptor.
std::set<int> udp_sockets() {
  std::set<int> fds;
  DIR* dir = ::opendir("/proc/self/fd");
  if (dir == nullptr) return fds;
  while (const dirent* entry = ::readdir(dir)) {
    const int fd = std::atoi(entry->d_name);
    if (fd <= 2 || fd == ::dirfd(dir)) continue;
    int domain = 0;
    int type = 0;
    socklen_t size = sizeof domain;
    if (::getsockopt(fd, SOL_SOCKET, SO_DOMAIN, &domain, &size) != 0) continue;
    size = sizeof type;
    if (::getsockopt(fd, SOL_SOCKET, SO_TYPE, &type, &size) != 0) continue;
    if (domain == AF_INET && type == SOCK_DGRAM) fds.insert(fd);
  }
  ::closedir(dir);
  return fds;
}

std::uint16_t local_port(int fd) {
  sockaddr_in address{};
  socklen_t size = sizeof address;
  if (::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &size) != 0) return 0;
  return ntohs(address.sin_port);
}

// An lcm_t publishing on `port`, with the descriptor of its transmit socket (the only datagram
// socket liblcm keeps open when nothing is subscribed).
struct Publisher {
  Lcm lcm;
  int send_fd = -1;

  explicit Publisher(int port) {
    const std::set<int> before = udp_sockets();
    lcm.reset(lcm_create(url(port).c_str()));
    if (!lcm) return;
    for (int fd : udp_sockets()) {
      if (!before.contains(fd)) send_fd = fd;
    }
  }

  void publish(const std::string& channel, const Bytes& payload) const {
    ASSERT_EQ(lcm_publish(lcm.get(), channel.c_str(), payload.data(),
                          static_cast<unsigned>(payload.size())),
              0);
  }
};

// The source address the kernel gives a datagram to the group (127.0.0.1 with the route on lo).
std::uint32_t source_address_to_group(int port) {
  const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in group{};
  group.sin_family = AF_INET;
  group.sin_port = htons(static_cast<std::uint16_t>(port));
  ::inet_pton(AF_INET, kGroup, &group.sin_addr);
  sockaddr_in local{};
  socklen_t size = sizeof local;
  if (::connect(fd, reinterpret_cast<const sockaddr*>(&group), sizeof group) != 0 ||
      ::getsockname(fd, reinterpret_cast<sockaddr*>(&local), &size) != 0) {
    ::close(fd);
    return 0;
  }
  ::close(fd);
  return ntohl(local.sin_addr.s_addr);
}

struct Message {
  std::string channel;
  Bytes payload;
  std::uint64_t session = 0;
};

struct Refusal {
  Rejection reason;
  std::size_t bytes;
  std::string channel;
};

struct Inbox {
  std::vector<Message> messages;
  std::vector<Refusal> refusals;
};

// Receives into `inbox` until `done` holds or `timeout` passes; returns `done()`.
bool pump(CommandSocket& socket, Inbox& inbox, const std::function<bool()>& done,
          std::chrono::milliseconds timeout = 5000ms) {
  const auto deadline = Clock::now() + timeout;
  while (!done()) {
    if (Clock::now() >= deadline) return false;
    pollfd entry{socket.fd(), POLLIN, 0};
    if (::poll(&entry, 1, 50) < 0) return false;
    socket.receive(
        [&](std::string_view channel, std::span<const std::uint8_t> payload,
            std::uint64_t session) {
          inbox.messages.push_back(
              {std::string(channel), Bytes(payload.begin(), payload.end()), session});
        },
        [&](const Rejected& rejected) {
          inbox.refusals.push_back(
              {rejected.reason, rejected.bytes, std::string(rejected.channel)});
        });
  }
  return true;
}

Bytes pattern(std::size_t size, std::uint8_t seed) {
  Bytes bytes(size);
  for (std::size_t i = 0; i < size; ++i)
    bytes[i] = static_cast<std::uint8_t>(seed + i * 7);
  return bytes;
}

// A plain UDP socket on 127.0.0.1 sending hand-made datagrams to the group.
class RawSender {
 public:
  explicit RawSender(int port) : fd_(::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0)) {
    group_.sin_family = AF_INET;
    group_.sin_port = htons(static_cast<std::uint16_t>(port));
    ::inet_pton(AF_INET, kGroup, &group_.sin_addr);
    sockaddr_in local{};
    local.sin_family = AF_INET;
    local.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ::bind(fd_, reinterpret_cast<const sockaddr*>(&local), sizeof local);
    const unsigned char ttl = 0;
    ::setsockopt(fd_, IPPROTO_IP, IP_MULTICAST_TTL, &ttl, sizeof ttl);
  }
  ~RawSender() { ::close(fd_); }
  RawSender(const RawSender&) = delete;
  RawSender& operator=(const RawSender&) = delete;

  void send(const Bytes& datagram) const {
    ASSERT_EQ(::sendto(fd_, datagram.data(), datagram.size(), 0,
                       reinterpret_cast<const sockaddr*>(&group_), sizeof group_),
              static_cast<ssize_t>(datagram.size()));
  }
  std::uint64_t session() const { return make_session(INADDR_LOOPBACK, local_port(fd_)); }

 private:
  int fd_;
  sockaddr_in group_{};
};

// Datagram builders, big-endian as liblcm writes them.
void put_u32(Bytes& out, std::uint32_t value) {
  for (int shift = 24; shift >= 0; shift -= 8)
    out.push_back(static_cast<std::uint8_t>(value >> shift));
}
void put_u16(Bytes& out, std::uint16_t value) {
  out.push_back(static_cast<std::uint8_t>(value >> 8));
  out.push_back(static_cast<std::uint8_t>(value));
}
void put_text(Bytes& out, const std::string& text, bool nul = true) {
  out.insert(out.end(), text.begin(), text.end());
  if (nul) out.push_back(0);
}

Bytes short_message(const std::string& channel, const Bytes& payload, std::uint32_t seqno = 1) {
  Bytes out;
  put_u32(out, 0x4c433032);
  put_u32(out, seqno);
  put_text(out, channel);
  out.insert(out.end(), payload.begin(), payload.end());
  return out;
}

Bytes fragment(std::uint32_t message_size, std::uint16_t number, std::uint16_t count,
               const std::string& channel, std::size_t data_bytes) {
  Bytes out;
  put_u32(out, 0x4c433033);
  put_u32(out, 7);
  put_u32(out, message_size);
  put_u32(out, 0);
  put_u16(out, number);
  put_u16(out, count);
  if (number == 0) put_text(out, channel);
  const Bytes data = pattern(data_bytes, 3);
  out.insert(out.end(), data.begin(), data.end());
  return out;
}

// The socket of a test, or a failure saying what to set up.
std::unique_ptr<CommandSocket> open_socket(int port) {
  try {
    return std::make_unique<CommandSocket>(url(port), kChannels);
  } catch (const TransportError& e) {
    ADD_FAILURE() << e.what() << "\n(run scripts/net-setup as root: LCM needs 224.0.0.0/4 on lo)";
    return nullptr;
  }
}

TEST(LcmCommandSocket, DeliversAcceptedChannelsWithTheSendersSession) {
  constexpr int kPort = 7690;
  const auto socket = open_socket(kPort);
  ASSERT_TRUE(socket);
  const Publisher first(kPort);
  const Publisher second(kPort);
  ASSERT_TRUE(first.lcm && second.lcm) << "lcm_create failed: is the multicast route on lo?";
  ASSERT_GE(first.send_fd, 0);
  ASSERT_GE(second.send_fd, 0);

  const Bytes wrench = pattern(200, 1);
  const Bytes control = pattern(40, 2);
  const Bytes again = pattern(1, 9);
  first.publish("RIGID_WRENCH", wrench);
  second.publish("RIGID_CONTROL", control);
  first.publish("RIGID_WRENCH", again);

  Inbox inbox;
  ASSERT_TRUE(pump(*socket, inbox, [&] { return inbox.messages.size() >= 3; }))
      << "received " << inbox.messages.size() << " of 3 messages within 5 s";
  ASSERT_EQ(inbox.messages.size(), 3U);
  EXPECT_EQ(inbox.messages[0].channel, "RIGID_WRENCH");
  EXPECT_EQ(inbox.messages[0].payload, wrench);
  EXPECT_EQ(inbox.messages[1].channel, "RIGID_CONTROL");
  EXPECT_EQ(inbox.messages[1].payload, control);
  EXPECT_EQ(inbox.messages[2].payload, again);

  // The session is the publisher's transmit socket: one lcm_t, one session.
  const std::uint32_t source = source_address_to_group(kPort);
  EXPECT_NE(source, 0U);
  EXPECT_EQ(inbox.messages[0].session, make_session(source, local_port(first.send_fd)));
  EXPECT_EQ(inbox.messages[1].session, make_session(source, local_port(second.send_fd)));
  EXPECT_EQ(inbox.messages[0].session, inbox.messages[2].session);
  EXPECT_NE(inbox.messages[0].session, inbox.messages[1].session);
  EXPECT_EQ(session_port(inbox.messages[0].session), local_port(first.send_fd));
  EXPECT_EQ(session_address(inbox.messages[0].session), source);

  EXPECT_TRUE(inbox.refusals.empty());
  const CommandSocketCounts counts = socket->counts();
  EXPECT_EQ(counts.datagrams, 3U);
  EXPECT_EQ(counts.delivered, 3U);
  EXPECT_EQ(counts.other_channel + counts.fragments + counts.malformed + counts.errors, 0U);
}

TEST(LcmCommandSocket, IgnoresOtherChannels) {
  constexpr int kPort = 7691;
  const auto socket = open_socket(kPort);
  ASSERT_TRUE(socket);
  const Publisher publisher(kPort);
  ASSERT_TRUE(publisher.lcm);

  publisher.publish("RIGID_STATE", pattern(300, 4));
  publisher.publish("P_RIGID_WRENCH", pattern(300, 4));  // another prefix: not ours
  publisher.publish("RIGID_WRENCH", pattern(10, 5));     // the marker that all have arrived

  Inbox inbox;
  ASSERT_TRUE(pump(*socket, inbox, [&] { return !inbox.messages.empty(); }));
  // Ordered: one sender socket, one receiving socket, loopback.
  ASSERT_EQ(inbox.messages.size(), 1U);
  EXPECT_EQ(inbox.messages[0].channel, "RIGID_WRENCH");
  EXPECT_EQ(inbox.messages[0].payload, pattern(10, 5));
  EXPECT_TRUE(inbox.refusals.empty());
  EXPECT_EQ(socket->counts().other_channel, 2U);
  EXPECT_EQ(socket->counts().datagrams, 3U);
  EXPECT_EQ(socket->malformed(), 0U);
}

TEST(LcmCommandSocket, DropsFragmentedMessagesWithoutAllocating) {
  constexpr int kPort = 7692;
  const auto socket = open_socket(kPort);
  ASSERT_TRUE(socket);
  const Publisher publisher(kPort);
  ASSERT_TRUE(publisher.lcm);

  // liblcm 1.3.1 fragments when channel + NUL + payload > 65499, in pieces of 65487 bytes.
  constexpr std::size_t kLarge = 200 * 1000;
  const auto fragments_of = [](const std::string& channel) {
    const std::size_t total = channel.size() + 1 + kLarge;
    return (total + 65486) / 65487;
  };
  // The largest unfragmented message on a channel is still delivered.
  const Bytes largest = pattern(65499 - std::string("RIGID_CONTROL").size() - 1, 6);
  publisher.publish("RIGID_WRENCH", pattern(kLarge, 7));
  publisher.publish("RIGID_STATE", pattern(kLarge, 8));
  publisher.publish("RIGID_CONTROL", largest);
  publisher.publish("RIGID_WRENCH", pattern(16, 9));  // marker

  // Non-allocating callbacks, so that any allocation counted is receive()'s own.
  std::size_t delivered = 0;
  std::size_t largest_delivered = 0;
  std::size_t rejected = 0;
  std::size_t rejected_as_wrench_fragment = 0;
  bool marker = false;
  const auto on_message = [&](std::string_view channel, std::span<const std::uint8_t> payload,
                              std::uint64_t) {
    ++delivered;
    if (channel == "RIGID_CONTROL" &&
        std::equal(payload.begin(), payload.end(), largest.begin(), largest.end())) {
      ++largest_delivered;
    }
    if (channel == "RIGID_WRENCH" && payload.size() == 16) marker = true;
  };
  const auto on_rejected = [&](const Rejected& r) {
    ++rejected;
    if (r.reason == Rejection::kFragment && r.channel == "RIGID_WRENCH") {
      ++rejected_as_wrench_fragment;
    }
  };

  // The counter counts (an explicit operator new call cannot be optimized away).
  rigid::test::reset_counted_allocations();
  {
    const rigid::test::CountingThread counting;
    ::operator delete(::operator new(16));
  }
  ASSERT_EQ(rigid::test::counted_allocations(), 1);

  rigid::test::reset_counted_allocations();
  const auto deadline = Clock::now() + 5s;
  while (!marker && Clock::now() < deadline) {
    pollfd entry{socket->fd(), POLLIN, 0};
    ASSERT_GE(::poll(&entry, 1, 50), 0);
    const rigid::test::CountingThread counting;
    socket->receive(on_message, on_rejected);
  }
  ASSERT_TRUE(marker) << "the marker message did not arrive within 5 s";
  EXPECT_EQ(rigid::test::counted_allocations(), 0) << "receive() allocated";

  EXPECT_EQ(delivered, 2U);  // the largest short message and the marker
  EXPECT_EQ(largest_delivered, 1U);
  const CommandSocketCounts counts = socket->counts();
  // The kernel's filter drops every fragment but each message's first before it is queued: of the
  // 4 + 4 sent, the socket reads 2.
  ASSERT_TRUE(socket->filtered());
  EXPECT_EQ(fragments_of("RIGID_WRENCH") + fragments_of("RIGID_STATE"), 8U);
  EXPECT_EQ(counts.fragments, 2U);
  EXPECT_EQ(socket->fragments_dropped(), counts.fragments);
  // Only the first fragment of a message on our channel is reported.
  EXPECT_EQ(rejected, 1U);
  EXPECT_EQ(rejected_as_wrench_fragment, 1U);
  EXPECT_EQ(counts.delivered, 2U);
  EXPECT_EQ(counts.malformed, 0U);
  EXPECT_EQ(counts.datagrams, counts.fragments + 2U);
}

TEST(LcmCommandSocket, CountsMalformedDatagramsAndNeverDeliversThem) {
  constexpr int kPort = 7693;
  const auto socket = open_socket(kPort);
  ASSERT_TRUE(socket);
  const RawSender sender(kPort);

  Bytes no_nul;
  put_u32(no_nul, 0x4c433032);
  put_u32(no_nul, 1);
  put_text(no_nul, "RIGID_WRENCH", false);
  Bytes header_only;
  put_u32(header_only, 0x4c433032);
  put_u32(header_only, 1);
  Bytes short_fragment;
  put_u32(short_fragment, 0x4c433033);
  put_u32(short_fragment, 1);
  put_u32(short_fragment, 0x10000000);
  const std::string garbage = "GET / HTTP/1.1\r\nHost: rigid\r\n\r\n";

  sender.send(Bytes(garbage.begin(), garbage.end()));                // bad magic
  sender.send({0x4c, 0x43, 0x30});                                   // too short
  sender.send(header_only);                                          // bad channel
  sender.send(no_nul);                                               // bad channel
  sender.send(short_message(std::string(64, 'A'), pattern(8, 1)));   // bad channel
  sender.send(short_fragment);                                       // too short
  sender.send(fragment(0x10000000, 0, 4100, "RIGID_WRENCH", 1000));  // 256 MB: fragment
  sender.send(fragment(0x10000000, 5, 4100, "", 60000));             // dropped by the kernel
  sender.send(short_message(std::string(63, 'A'), pattern(8, 1)));   // other channel
  sender.send(short_message("RIGID_WRENCH", {}));                    // empty payload
  sender.send(short_message("RIGID_CONTROL", {1, 2, 3}));            // marker

  Inbox inbox;
  ASSERT_TRUE(pump(*socket, inbox, [&] { return inbox.messages.size() >= 2; }));
  ASSERT_EQ(inbox.messages.size(), 2U);
  EXPECT_EQ(inbox.messages[0].channel, "RIGID_WRENCH");
  EXPECT_TRUE(inbox.messages[0].payload.empty());
  EXPECT_EQ(inbox.messages[1].channel, "RIGID_CONTROL");
  EXPECT_EQ(inbox.messages[1].payload, (Bytes{1, 2, 3}));
  EXPECT_EQ(inbox.messages[1].session, sender.session());

  ASSERT_EQ(inbox.refusals.size(), 7U);
  const std::vector<Rejection> reasons{
      Rejection::kBadMagic,   Rejection::kTooShort, Rejection::kBadChannel, Rejection::kBadChannel,
      Rejection::kBadChannel, Rejection::kTooShort, Rejection::kFragment};
  for (std::size_t i = 0; i < reasons.size(); ++i) {
    EXPECT_EQ(inbox.refusals[i].reason, reasons[i])
        << "datagram " << i << ": " << to_string(inbox.refusals[i].reason);
  }
  EXPECT_EQ(inbox.refusals[0].bytes, garbage.size());
  EXPECT_EQ(inbox.refusals[1].bytes, 3U);
  EXPECT_EQ(inbox.refusals[6].channel, "RIGID_WRENCH");
  EXPECT_TRUE(inbox.refusals[0].channel.empty());

  const CommandSocketCounts counts = socket->counts();
  ASSERT_TRUE(socket->filtered());
  EXPECT_EQ(counts.datagrams, 10U);  // 11 sent, fragment 5 never queued
  EXPECT_EQ(counts.malformed, 6U);
  EXPECT_EQ(socket->malformed(), 6U);
  EXPECT_EQ(counts.fragments, 1U);
  EXPECT_EQ(counts.other_channel, 1U);
  EXPECT_EQ(counts.delivered, 2U);
}

TEST(LcmCommandSocket, SharesThePortWithLiblcmAndOtherSockets) {
  constexpr int kPort = 7694;
  const auto first = open_socket(kPort);
  ASSERT_TRUE(first);
  const auto second = open_socket(kPort);
  ASSERT_TRUE(second);
  Lcm subscriber(lcm_create(url(kPort).c_str()));
  ASSERT_TRUE(subscriber);
  int lcm_received = 0;
  lcm_subscribe(
      subscriber.get(), "RIGID_WRENCH",
      [](const lcm_recv_buf_t*, const char*, void* user) { ++*static_cast<int*>(user); },
      &lcm_received);
  const Publisher publisher(kPort);
  ASSERT_TRUE(publisher.lcm);
  publisher.publish("RIGID_WRENCH", pattern(100, 1));

  Inbox first_inbox;
  Inbox second_inbox;
  EXPECT_TRUE(pump(*first, first_inbox, [&] { return !first_inbox.messages.empty(); }));
  EXPECT_TRUE(pump(*second, second_inbox, [&] { return !second_inbox.messages.empty(); }));
  for (int i = 0; i < 50 && lcm_received == 0; ++i)
    lcm_handle_timeout(subscriber.get(), 100);
  EXPECT_EQ(lcm_received, 1);
}

TEST(LcmCommandSocket, ParsesUdpmUrls) {
  const UdpmEndpoint endpoint =
      parse_udpm_url("udpm://239.255.76.67:7667?ttl=0&recv_buf_size=2097152");
  EXPECT_EQ(endpoint.group, 0xefff4c43U);
  EXPECT_EQ(endpoint.port, 7667);
  EXPECT_EQ(endpoint.recv_buf_size, 2097152);

  const UdpmEndpoint defaults = parse_udpm_url("udpm://");
  EXPECT_EQ(defaults.group, 0xefff4c43U);
  EXPECT_EQ(defaults.port, 7667);
  EXPECT_EQ(defaults.recv_buf_size, 0);

  EXPECT_EQ(parse_udpm_url("udpm://239.1.2.3:9000?recv_buf_size=100?ttl=1").recv_buf_size, 100);
}

TEST(LcmCommandSocket, RefusesBadUrlsNamingThem) {
  for (const std::string bad :
       {"tcpq://239.255.76.67:7667", "239.255.76.67:7667", "udpm://239.255.76.67",
        "udpm://10.1.2.3:7667?ttl=0", "udpm://999.0.0.1:7667", "udpm://239.255.76.67:0",
        "udpm://239.255.76.67:70000", "udpm://239.255.76.67:0x1df3",
        "udpm://239.255.76.67:7667?recv_buf_size=lots", "udpm://239.255.76.67:7667?recv_buf_size",
        ""}) {
    try {
      CommandSocket socket(bad, kChannels);
      ADD_FAILURE() << "accepted " << bad;
    } catch (const TransportError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("'" + bad + "'"), std::string::npos) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
  }
  EXPECT_THROW(CommandSocket(url(7695), {std::string(64, 'C')}), TransportError);
}

}  // namespace
}  // namespace rigid::transport::lcm
