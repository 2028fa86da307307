// rigidd's own receiver for commands sent over LCM's udpm transport.
//
// Why: liblcm reassembles fragmented messages of up to LCM_MAX_MESSAGE_SIZE (256 MB) per sender,
// allocating the whole announced size on the first fragment; a peer that never sends the last
// fragment keeps that memory resident in the receiver. Commands never need fragmenting: liblcm
// (1.3.1, Linux) sends a message in one datagram while channel + NUL + payload fit in 65499 bytes,
// and an encoded wrench or control is a few hundred bytes. So rigidd reads the multicast group
// itself, with one fixed 64 KB buffer, and drops every fragment unread.
//
// What it does: one UDP socket joined to the LCM group of a udpm:// URL; each datagram is parsed
// as liblcm 1.3.1 frames it (big-endian header; see the .cpp) and a short message on one of the
// accepted channels is handed to the caller with the sender's address and port as its session.
//
// What it does not do: reassemble fragments, decode payloads, deduplicate or order messages by
// their sequence number, authenticate senders (a session is only "this source address and port";
// anything able to send to the group can claim any channel), or publish. Everything sent to the
// group reaches this socket, rigidd's own states included; a filter in the kernel drops every
// fragment but a message's first before it is queued (so a large world's states neither cost this
// socket's reader a copy nor fill its receive buffer), but the states of small worlds (one
// datagram each) and everything else come through: read it promptly and give it a receive buffer
// (recv_buf_size) sized for that traffic, or the kernel drops commands with the rest.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "transport/transport.hpp"

namespace rigid::transport::lcm {

// What a udpm:// URL says about where to receive. Addresses and ports are in host byte order.
struct UdpmEndpoint {
  std::uint32_t group = 0;  // an IPv4 multicast address
  std::uint16_t port = 0;   // never 0
  int recv_buf_size = 0;    // SO_RCVBUF to request; 0: the kernel's default
};

// Parses "udpm://<group>:<port>?<key>=<value>&..." as liblcm does, but strictly: throws
// TransportError (one line naming the URL) for another provider, a group that is not a dotted
// IPv4 multicast address, a missing or non-decimal port, or a recv_buf_size that is not a
// non-negative decimal int. "udpm://" alone means liblcm's default, 239.255.76.67:7667. Other keys
// (ttl, ...) concern senders and are ignored.
UdpmEndpoint parse_udpm_url(std::string_view url);

// A session is the sender's IPv4 address and UDP port: each lcm_t sends from its own socket, so a
// client restarted (a new ephemeral port) is a new session.
constexpr std::uint64_t make_session(std::uint32_t address, std::uint16_t port) {
  return (std::uint64_t{address} << 16) | port;
}
constexpr std::uint32_t session_address(std::uint64_t session) {
  return static_cast<std::uint32_t>(session >> 16);
}
constexpr std::uint16_t session_port(std::uint64_t session) {
  return static_cast<std::uint16_t>(session & 0xffffU);
}

// Why a datagram was refused.
enum class Rejection : std::uint8_t {
  kTooShort,    // shorter than the header its magic announces (8 bytes short, 20 fragment)
  kBadMagic,    // neither "LC02" (short message) nor "LC03" (fragment)
  kBadChannel,  // the channel name has no NUL within the datagram and LCM's 63 characters
  kFragment,    // "LC03": a fragment of a message too large for one datagram; never reassembled
};
std::string_view to_string(Rejection rejection);

// A refused datagram, as reported to receive()'s on_rejected. `channel` is empty unless the
// datagram is the first fragment of a message on an accepted channel.
struct Rejected {
  Rejection reason;
  std::size_t bytes;      // the datagram's size
  std::uint64_t session;  // its sender
  std::string_view channel;
};

// Totals since construction. Readable from any thread.
struct CommandSocketCounts {
  std::uint64_t datagrams = 0;      // read from the socket, whatever they held
  std::uint64_t delivered = 0;      // short messages on an accepted channel
  std::uint64_t other_channel = 0;  // short messages on another channel (ignored silently)
  std::uint64_t fragments = 0;      // first fragments, on any channel (rigidd's own states
                                    // included); the kernel drops the others unread
  std::uint64_t malformed = 0;      // too short, bad magic or bad channel
  std::uint64_t errors = 0;         // recvfrom failures other than "nothing to read"
};

// One UDP socket on an LCM udpm group: bound to the group's address and port with SO_REUSEADDR
// (as liblcm does on Linux, so it shares the port with every lcm_t of this and other processes),
// joined on INADDR_ANY, non-blocking and close-on-exec. Bound to the group address rather than
// INADDR_ANY (where liblcm binds), it never sees unicast datagrams sent to the port.
//
// Not thread-safe, except counts() and its shorthands: one thread calls receive(). Memory is fixed
// at construction: receiving allocates nothing.
class CommandSocket {
 public:
  // Datagrams read by one receive() call at most, so that a flood cannot starve the caller.
  static constexpr int kMaxDatagramsPerCall = 256;
  // The receive buffer: the largest UDP payload over IPv4 (65507 bytes) fits.
  static constexpr std::size_t kBufferBytes = 65536;

  // `channels`: the channel names whose messages are delivered (at most 63 characters each, as in
  // LCM). Throws TransportError (one line naming the URL) when the URL is refused by
  // parse_udpm_url or the socket cannot be set up (for instance: no multicast route).
  CommandSocket(std::string_view url, std::vector<std::string> channels);
  ~CommandSocket();

  CommandSocket(const CommandSocket&) = delete;
  CommandSocket& operator=(const CommandSocket&) = delete;
  CommandSocket(CommandSocket&&) = delete;
  CommandSocket& operator=(CommandSocket&&) = delete;

  // For poll(): readable when datagrams are pending.
  int fd() const { return fd_; }
  const UdpmEndpoint& endpoint() const { return endpoint_; }
  // SO_RCVBUF as the kernel reports it (Linux doubles the request and caps it at rmem_max).
  int receive_buffer_bytes() const;
  // Whether the kernel took the filter that drops every fragment but the first (see the .cpp);
  // without it those are read and counted too.
  bool filtered() const { return filtered_; }

  // Reads the pending datagrams, at most kMaxDatagramsPerCall, without blocking, and returns how
  // many were read (0: none pending). For each:
  //  - a short message on an accepted channel: on_message(std::string_view channel,
  //    std::span<const std::uint8_t> payload, std::uint64_t session). Both views point into this
  //    socket's buffer and are valid only during the call.
  //  - a short message on another channel: nothing (counted).
  //  - a malformed datagram, or the first fragment of a message on an accepted channel (a command
  //    too large to be one): on_rejected(const Rejected&), if given. The first fragments of other
  //    channels' messages (rigidd's own large states) are only counted; later fragments never
  //    reach the socket (filtered()).
  // Callbacks may throw; the datagram being handled is then consumed, the rest stay queued.
  template <class OnMessage>
  int receive(OnMessage&& on_message) {
    return receive(std::forward<OnMessage>(on_message), [](const Rejected&) {});
  }
  template <class OnMessage, class OnRejected>
  int receive(OnMessage&& on_message, OnRejected&& on_rejected) {
    int read = 0;
    while (read < kMaxDatagramsPerCall) {
      const Datagram datagram = next();
      if (datagram.kind == Kind::kNone) break;
      ++read;
      if (datagram.kind == Kind::kMessage) {
        on_message(datagram.channel, datagram.payload, datagram.session);
      } else if (datagram.kind == Kind::kRejected) {
        on_rejected(Rejected{datagram.reason, datagram.bytes, datagram.session, datagram.channel});
      }
    }
    return read;
  }

  CommandSocketCounts counts() const;
  std::uint64_t fragments_dropped() const { return fragments_.load(std::memory_order_relaxed); }
  std::uint64_t malformed() const { return malformed_.load(std::memory_order_relaxed); }

 private:
  enum class Kind : std::uint8_t { kNone, kMessage, kIgnored, kRejected };
  struct Datagram {
    Kind kind = Kind::kNone;
    Rejection reason = Rejection::kTooShort;
    std::size_t bytes = 0;
    std::uint64_t session = 0;
    std::string_view channel;
    std::span<const std::uint8_t> payload;
  };

  // Reads and classifies one datagram; kNone when none is pending (or reading failed).
  Datagram next();
  bool accepts(std::string_view channel) const;

  UdpmEndpoint endpoint_;
  std::vector<std::string> channels_;
  std::unique_ptr<std::uint8_t[]> buffer_;
  int fd_ = -1;
  bool filtered_ = false;

  std::atomic<std::uint64_t> datagrams_{0};
  std::atomic<std::uint64_t> delivered_{0};
  std::atomic<std::uint64_t> other_channel_{0};
  std::atomic<std::uint64_t> fragments_{0};
  std::atomic<std::uint64_t> malformed_{0};
  std::atomic<std::uint64_t> errors_{0};
};

}  // namespace rigid::transport::lcm
