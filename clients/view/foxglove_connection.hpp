// One Foxglove client (foxglove.websocket.v1, foxglove_protocol.hpp) of rigid-view's server: sent
// serverInfo and the channels when it connects, then on each channel it subscribes to the newest
// message when it subscribes and each message after; its client-published pushes go to the same
// command handler as the page's.
//
// Flow control, as for a page (server.hpp): one write in flight; per channel a newest-only slot,
// so a message that arrives while the previous one waits replaces it (counted), and a slow client
// gets fewer messages, never a growing queue; texts (status) queue up to kMaxQueuedTexts. Limits
// as for a page: kMaxBadFrames refused messages, then the connection is closed; messages larger
// than foxglove::kMaxClientText close it.
#pragma once

#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <deque>
#include <map>
#include <memory>
#include <optional>

#include "foxglove_protocol.hpp"
#include "server.hpp"

namespace rigid::view {

class FoxgloveConnection : public std::enable_shared_from_this<FoxgloveConnection> {
 public:
  FoxgloveConnection(ViewServer::Impl& impl, boost::asio::ip::tcp::socket socket, std::uint64_t id);

  // Completes the handshake (choosing the subprotocol) and starts reading.
  void accept(boost::beast::http::request<boost::beast::http::string_body> request);
  // A message of `channel` for this client, if it subscribes to it.
  void send(foxglove::Channel channel, const FoxgloveMessage& message);
  void close();

 private:
  void read();
  void on_frame();
  void on_text(const std::string& text);
  void on_binary(const std::string& bytes);
  void refuse(const std::string& why);
  void send_text(std::string text);
  void write_next();
  void fail();
  void unsubscribe_all();

  ViewServer::Impl& impl_;
  boost::beast::websocket::stream<boost::beast::tcp_stream> ws_;
  boost::beast::flat_buffer in_;
  std::uint64_t id_;
  std::deque<Bytes> texts_;
  std::array<std::optional<FoxgloveMessage>, foxglove::kChannelCount> slots_;
  std::array<std::optional<std::uint32_t>, foxglove::kChannelCount> subscription_;  // its id
  std::size_t next_slot_ = 0;  // round robin over the channels' slots
  std::array<char, 13> header_{};
  std::map<std::uint32_t, bool> client_channels_;  // advertised by the client (all push)
  bool writing_ = false;
  bool open_ = false;
  bool closed_ = false;
  std::size_t bad_frames_ = 0;
};

}  // namespace rigid::view
