// rigid-view's WebSocket server (server.hpp) against a client written here with Boost.Beast, over
// loopback TCP in one process: what it refuses and whom it drops, as the README promises. A
// WebSocket from a page of another origin is refused (403) while the page's own origin, and a
// client that sends none (not a browser), are let in; at most 16 pages at once (the 17th is
// refused, 503, and gets in once a page has left); a page that sends more than 20 bad frames is
// disconnected (policy error), one that sends 20 is not. Every wait is bounded.
#include <gtest/gtest.h>
#include <unistd.h>

#include <boost/asio.hpp>
#include <boost/asio/use_future.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <future>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "protocol.hpp"
#include "server.hpp"

namespace rigid::view {
namespace {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using tcp = net::ip::tcp;
using namespace std::chrono_literals;

constexpr auto kPatience = 5s;

// A page of one file, listed as rigid-view reads its page (served_files.txt).
class WebDir {
 public:
  WebDir()
      : dir_(std::filesystem::temp_directory_path() /
             ("rigid-view-server-test-" + std::to_string(::getpid()))) {
    std::filesystem::create_directories(dir_);
    std::ofstream(dir_ / "index.html") << "<!doctype html><title>stand-in</title>\n";
    std::ofstream(dir_ / "served_files.txt") << "index.html\n";
  }
  ~WebDir() { std::filesystem::remove_all(dir_); }
  const std::filesystem::path& path() const { return dir_; }

 private:
  std::filesystem::path dir_;
};

// A WebSocket client on its own I/O thread; each operation waits at most kPatience.
class Client {
 public:
  explicit Client(net::io_context& ioc) : ws_(ioc) {}

  // Connects and asks to upgrade /ws with this Origin header (none when empty): the HTTP status
  // of the answer, 101 when the WebSocket is open.
  unsigned open(std::uint16_t port, const std::string& origin) {
    beast::get_lowest_layer(ws_).connect(tcp::endpoint(net::ip::make_address("127.0.0.1"), port));
    if (!origin.empty()) {
      ws_.set_option(websocket::stream_base::decorator(
          [origin](websocket::request_type& req) { req.set(http::field::origin, origin); }));
    }
    websocket::response_type response;
    auto done =
        ws_.async_handshake(response, "127.0.0.1:" + std::to_string(port), "/ws", net::use_future);
    if (!finished(done)) return 0;
    try {
      done.get();
    } catch (const boost::system::system_error&) {
      // upgrade_declined: the status says why
    }
    return response.result_int();
  }

  // The next text frame; nothing when the connection closed (or nothing came in time).
  std::optional<std::string> read() {
    buffer_.clear();
    auto done = ws_.async_read(buffer_, net::use_future);
    if (!finished(done)) return std::nullopt;
    try {
      done.get();
    } catch (const boost::system::system_error& e) {
      closed_by_server_ = e.code() == websocket::error::closed;
      return std::nullopt;
    }
    return beast::buffers_to_string(buffer_.data());
  }

  bool send(const std::string& text) {
    ws_.text(true);
    auto done = ws_.async_write(net::buffer(text), net::use_future);
    if (!finished(done)) return false;
    try {
      done.get();
      return true;
    } catch (const boost::system::system_error&) {
      return false;
    }
  }

  bool closed_by_server() const { return closed_by_server_; }
  websocket::close_code close_code() const {
    return static_cast<websocket::close_code>(ws_.reason().code);
  }

 private:
  template <typename T>
  bool finished(std::future<T>& f) {
    if (f.wait_for(kPatience) == std::future_status::ready) return true;
    beast::get_lowest_layer(ws_).cancel();
    f.wait();
    return false;
  }

  websocket::stream<beast::tcp_stream> ws_;
  beast::flat_buffer buffer_;
  bool closed_by_server_ = false;
};

class ViewServerTest : public ::testing::Test {
 protected:
  ViewServerTest() : work_(net::make_work_guard(ioc_)), io_([this] { ioc_.run(); }) {}
  ~ViewServerTest() override {
    clients_.clear();
    work_.reset();
    ioc_.stop();
    io_.join();
  }

  // A server on a free port; valid commands are answered "ok".
  void start(ServerOptions options = {}) {
    options.port = 0;
    options.web_dir = web_.path();
    server_ = std::make_unique<ViewServer>(
        options,
        [](std::uint64_t, const PageCommand& c, std::function<void(Bytes)> reply) {
          reply(std::make_shared<const std::string>(
              reply_json(c.id, op_name(c.op), true, "ok", 0, "")));
        },
        nullptr);
    server_->start();
  }
  std::string own_origin() const { return "http://127.0.0.1:" + std::to_string(server_->port()); }

  // A new client, connected with `origin`; its status in *status.
  Client& connect(const std::string& origin, unsigned* status) {
    clients_.push_back(std::make_unique<Client>(ioc_));
    *status = clients_.back()->open(server_->port(), origin);
    return *clients_.back();
  }
  // A page in: upgraded and greeted with hello.
  ::testing::AssertionResult page(Client** out = nullptr) {
    unsigned status = 0;
    Client& c = connect(own_origin(), &status);
    if (status != 101) return ::testing::AssertionFailure() << "status " << status;
    const auto hello = c.read();
    if (!hello || hello->find("\"type\":\"hello\"") == std::string::npos)
      return ::testing::AssertionFailure() << "no hello: " << hello.value_or("(closed)");
    if (out != nullptr) *out = &c;
    return ::testing::AssertionSuccess();
  }

  net::io_context ioc_;
  net::executor_work_guard<net::io_context::executor_type> work_;
  std::thread io_;
  WebDir web_;
  std::unique_ptr<ViewServer> server_;
  std::vector<std::unique_ptr<Client>> clients_;
};

TEST_F(ViewServerTest, AWebSocketFromAnotherOriginIsRefusedWith403) {
  start();
  unsigned status = 0;
  connect("http://evil.example", &status);
  EXPECT_EQ(status, 403u);
  connect("http://127.0.0.1:1", &status);  // the same host on another port is another origin
  EXPECT_EQ(status, 403u);
  EXPECT_EQ(server_->counts().connections_refused.load(), 2);
  // The page's own origin is let in, and so is a client that sends none (not a browser).
  EXPECT_TRUE(page());
  connect("", &status);
  EXPECT_EQ(status, 101u);
  EXPECT_EQ(server_->counts().connections_refused.load(), 2);
}

// --listen localhost:PORT: the name is resolved to its (IPv4) loopback address, where a page
// connects; that address is not beyond the host (no warning).
TEST_F(ViewServerTest, AHostNameIsResolvedAndServed) {
  ServerOptions options;
  options.host = "localhost";
  start(options);
  EXPECT_EQ(server_->address(), "127.0.0.1");
  EXPECT_FALSE(server_->listens_beyond_host());
  EXPECT_TRUE(page());
  ServerOptions nowhere;
  nowhere.host = "no-such-host.invalid";  // RFC 2606: never resolves
  nowhere.web_dir = web_.path();
  try {
    ViewServer s(nowhere, nullptr, nullptr);
    ADD_FAILURE() << "bound a name that does not resolve";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()).rfind("--listen: cannot resolve no-such-host.invalid: ", 0), 0u)
        << e.what();
  }
}

TEST_F(ViewServerTest, AtMost16PagesAtOnce) {
  start();
  ASSERT_EQ(ServerOptions{}.max_pages, 16u);  // rigid-view's default, the README's figure
  std::vector<Client*> pages;
  for (int i = 0; i < 16; ++i) {
    Client* c = nullptr;
    ASSERT_TRUE(page(&c)) << "page " << i + 1;
    pages.push_back(c);
  }
  unsigned status = 0;
  connect(own_origin(), &status);
  EXPECT_EQ(status, 503u) << "a 17th page";
  EXPECT_EQ(server_->counts().connections_refused.load(), 1);
  // One page leaves (its socket closes: the server sees it on its next read): a newcomer gets in.
  clients_.erase(clients_.begin());
  bool in = false;
  for (const auto deadline = std::chrono::steady_clock::now() + kPatience;
       !in && std::chrono::steady_clock::now() < deadline;) {
    in = page();
    if (!in) std::this_thread::sleep_for(20ms);
  }
  EXPECT_TRUE(in) << "no room after a page left";
}

TEST_F(ViewServerTest, APageThatSendsMoreThan20BadFramesIsDisconnected) {
  start();
  Client* c = nullptr;
  ASSERT_TRUE(page(&c));
  // Twenty bad frames: each refused with a reason, and the page stays: a command still works.
  for (int i = 0; i < 20; ++i) {
    ASSERT_TRUE(c->send("not json " + std::to_string(i)));
    const auto answer = c->read();
    ASSERT_TRUE(answer) << "dropped after " << i + 1 << " bad frames";
    EXPECT_NE(answer->find("\"type\":\"error\""), std::string::npos) << *answer;
  }
  ASSERT_TRUE(c->send(R"({"op":"pause","id":7})"));
  const auto reply = c->read();
  ASSERT_TRUE(reply) << "dropped after 20 bad frames";
  EXPECT_NE(reply->find("\"type\":\"reply\",\"id\":7"), std::string::npos) << *reply;
  // The 21st: refused, then the connection is closed as a policy error.
  ASSERT_TRUE(c->send("{\"op\":\"fly\"}"));
  const auto last = c->read();
  ASSERT_TRUE(last);
  EXPECT_NE(last->find("\"type\":\"error\""), std::string::npos) << *last;
  EXPECT_FALSE(c->read()) << "still connected after 21 bad frames";
  EXPECT_TRUE(c->closed_by_server());
  EXPECT_EQ(c->close_code(), websocket::close_code::policy_error);
  EXPECT_EQ(server_->counts().frames_refused.load(), 21);
}

}  // namespace
}  // namespace rigid::view
