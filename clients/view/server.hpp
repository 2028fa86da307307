// rigid-view's HTTP and WebSocket server (Boost.Beast on one Asio thread): serves the page's few
// files from memory (those its web directory's served_files.txt names, loaded at start) and one
// WebSocket per page at /ws.
//
// Each page connection has a "latest state" slot and a short queue of texts: a state that arrives
// while the previous one is still being written, or while the page has frames not yet
// acknowledged as drawn (kMaxUnackedStates, kMaxUnackedBytes), replaces the one waiting (dropped,
// counted), so a slow page gets fewer frames and never an unbounded queue, in rigid-view or in the
// sockets' buffers. Texts (scene, stats, answers) queue up to kMaxQueuedTexts; beyond that the
// oldest is dropped.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <thread>
#include <utility>  // before Asio: Boost 1.74's asio/awaitable.hpp needs std::exchange
#include <vector>

#include "foxglove_protocol.hpp"
#include "protocol.hpp"

namespace rigid::view {

using Bytes = std::shared_ptr<const std::string>;

struct ServerCounts {
  std::atomic<std::int64_t> pages_connected{0};
  std::atomic<std::int64_t> connections_refused{0};  // too many, bad origin
  std::atomic<std::int64_t> http_refused{0};         // unknown path, method, bad request
  std::atomic<std::int64_t> frames_refused{0};       // garbage, binary, huge, unknown commands
  std::atomic<std::int64_t> commands_refused{0};     // --read-only, busy
  std::atomic<std::int64_t> states_sent{0};
  std::atomic<std::int64_t> states_dropped{0};  // replaced in a slow page's slot
  std::atomic<std::int64_t> texts_dropped{0};
  // Foxglove clients (foxglove_connection.hpp): connected, messages written, and messages
  // replaced in a slow client's newest-only slot of their channel.
  std::atomic<std::int64_t> foxglove_clients{0};
  std::atomic<std::int64_t> foxglove_sent{0};
  std::atomic<std::int64_t> foxglove_dropped{0};
};

// rigid-view's closing line: "stopped; pages N, states sent N, ..." (without the program name).
std::string describe(const ServerCounts& c);

struct ServerOptions {
  std::string host = "127.0.0.1";  // an address, or a host name to resolve
  std::uint16_t port = 8765;
  bool read_only = false;
  std::filesystem::path web_dir;
  std::size_t max_pages = 16;
  bool playback = false;  // rigid-view FILE: hello says so; commands are checked for the mode
  // Origins (exact, e.g. https://app.foxglove.dev) whose Foxglove clients may connect besides
  // those that send no Origin or the page's own (docs/foxglove.md).
  std::vector<std::string> foxglove_origins;
};

// A message of a Foxglove channel: its protobuf bytes and its time (ns since the epoch).
struct FoxgloveMessage {
  Bytes payload;
  std::uint64_t time_ns = 0;
};

class ViewServer {
 public:
  static constexpr std::size_t kMaxQueuedTexts = 64;
  static constexpr std::size_t kMaxBadFrames = 20;  // then the page is disconnected
  // State frames written to a page and not yet acknowledged ({"op":"ack"}, protocol.hpp): more
  // wait in its newest-only slot. Up to four, as long as they hold at most kMaxUnackedBytes (the
  // first always goes). The page acknowledges what arrived once its next frame is drawn, and that
  // frame applies only the newest (app.js), so the states in flight cost it a receipt each, not a
  // decode; what they buy is a state published just before the frame being there for it. With one
  // in flight, the next state would leave rigid-view only when the page's frame was drawn, arrive
  // just after the next frame had started and wait a whole frame (bench/notes/view.md). A page
  // that stops drawing stops acknowledging: rigid-view then sends it nothing more.
  static constexpr std::size_t kMaxUnackedStates = 4;
  static constexpr std::size_t kMaxUnackedBytes = std::size_t{4} << 20;

  // Called on the server thread for each valid command of a page (with --read-only, only watch:
  // the others are refused). `reply` sends a text to that page only (any thread).
  using CommandHandler = std::function<void(std::uint64_t page, const PageCommand& command,
                                            std::function<void(Bytes)> reply)>;
  // What a newly connected page gets first (scene, last stats), on the server thread.
  using Greeting = std::function<std::vector<Bytes>()>;
  // The newest message of a Foxglove channel, for a client that subscribes to it (payload null:
  // none yet), on the server thread. Without it rigid-view serves no Foxglove client.
  using FoxgloveLatest = std::function<FoxgloveMessage(foxglove::Channel)>;

  // Loads the page's files and binds. Throws std::runtime_error (one line) on failure.
  ViewServer(const ServerOptions& options, CommandHandler on_command, Greeting greeting,
             FoxgloveLatest foxglove_latest = {});
  ~ViewServer();
  ViewServer(const ViewServer&) = delete;
  ViewServer& operator=(const ViewServer&) = delete;

  std::uint16_t port() const;
  std::string address() const;  // the address it listens on (a host name resolved)
  // Whether other hosts can reach it (the address is not loopback).
  bool listens_beyond_host() const;
  void start();  // the server thread
  void stop();   // closes everything and joins
  // Any thread.
  void broadcast_state(Bytes frame);
  void broadcast_text(Bytes text);
  // Foxglove: whether any client subscribes to the channel (its messages are made only then),
  // a message to its subscribers, and the bodies a client's push may name (any thread).
  bool foxglove_subscribed(foxglove::Channel channel) const;
  void broadcast_foxglove(foxglove::Channel channel, FoxgloveMessage message);
  void set_body_ids(std::map<std::string, std::int32_t, std::less<>> ids);
  const ServerCounts& counts() const;

  class Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace rigid::view
