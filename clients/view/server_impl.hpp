// ViewServer's state, shared by its connections: the page's (server.cpp) and Foxglove clients'
// (foxglove_connection.cpp). Everything here is touched on the server thread only, except the
// counts and the subscriber counts (atomics, read by any thread).
#pragma once

#include <array>
#include <atomic>
#include <boost/asio.hpp>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <thread>

#include "foxglove_protocol.hpp"
#include "server.hpp"

namespace rigid::view {

struct File {
  std::string type;
  std::string body;
};

class Page;
class FoxgloveConnection;

class ViewServer::Impl {
 public:
  ServerOptions options;
  CommandHandler on_command;
  Greeting greeting;
  FoxgloveLatest foxglove_latest;
  ServerCounts counts;
  std::map<std::string, File, std::less<>> files;
  boost::asio::io_context ioc{1};
  boost::asio::ip::tcp::acceptor acceptor{ioc};
  std::thread thread;
  std::set<std::shared_ptr<Page>> pages;
  std::set<std::shared_ptr<FoxgloveConnection>> foxglove_clients;
  std::uint64_t next_page = 1;  // pages and Foxglove clients: one id each, one push key each
  std::shared_ptr<std::size_t> http_sessions = std::make_shared<std::size_t>(0);
  // Per channel, the Foxglove clients subscribed to it.
  std::array<std::atomic<int>, foxglove::kChannelCount> subscribers{};
  std::map<std::string, std::int32_t, std::less<>> body_ids;  // by name, for Foxglove pushes
  std::string session_id;                                     // Foxglove's serverInfo
  std::set<std::string> refused_origins;  // Foxglove origins refused and printed (at most 8)

  // Pages and Foxglove clients together, against options.max_pages.
  std::size_t connections() const { return pages.size() + foxglove_clients.size(); }
  void accept();
};

}  // namespace rigid::view
