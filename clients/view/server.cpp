#include "server.hpp"

#include <algorithm>
#include <array>
#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <chrono>
#include <deque>
#include <fstream>
#include <future>
#include <iostream>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <utility>

#include "foxglove_connection.hpp"
#include "server_impl.hpp"

namespace rigid::view {
namespace {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using tcp = net::ip::tcp;
using namespace std::chrono_literals;

constexpr std::size_t kMaxHttpSessions = 64;

// The page's files: web_dir/kServedList names them, one path (relative to web_dir) a line, as the
// build writes it from the one list of the page's files (clients/view/CMakeLists.txt); each is
// served at "/" + its path (index.html at "/"), with the content type of its extension. Nothing
// else in web_dir is served. Bounded: the memory they take is read once, at start.
constexpr std::string_view kServedList = "served_files.txt";
constexpr std::size_t kMaxServedFiles = 256;
constexpr std::size_t kMaxServedPath = 200;                           // characters of one path
constexpr std::uintmax_t kMaxServedBytes = std::uintmax_t{64} << 20;  // all files together

constexpr std::array<std::pair<std::string_view, std::string_view>, 3> kContentTypes{{
    {".html", "text/html; charset=utf-8"},
    {".js", "text/javascript; charset=utf-8"},
    {".css", "text/css; charset=utf-8"},
}};

// The content type for a path of the list, or "" if it is not a path the page's files may have:
// relative, without "." or ".." parts or empty ones, of letters, digits, '_', '-', '.' and '/'.
std::string_view served_type(std::string_view path) {
  if (path.empty() || path.size() > kMaxServedPath || path.front() == '/') return {};
  for (const char c : path) {
    const bool plain = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                       c == '_' || c == '-' || c == '.' || c == '/';
    if (!plain) return {};
  }
  for (std::size_t start = 0; start <= path.size();) {
    const std::size_t end = std::min(path.find('/', start), path.size());
    const std::string_view part = path.substr(start, end - start);
    if (part.empty() || part == "." || part == "..") return {};
    start = end + 1;
  }
  for (const auto& [extension, type] : kContentTypes)
    if (path.size() > extension.size() && path.ends_with(extension)) return type;
  return {};
}

[[noreturn]] void no_page(const std::filesystem::path& web_dir, const std::string& what) {
  throw std::runtime_error("the page's files in " + web_dir.string() + ": " + what +
                           " (--web-dir; three.js: npm ci in clients/view/web, then rebuild)");
}

// URL path -> the file, read from web_dir as its kServedList names them; or throws, naming the
// list's line or the file at fault.
std::map<std::string, File, std::less<>> read_page(const std::filesystem::path& web_dir) {
  const std::filesystem::path list_path = web_dir / kServedList;
  std::error_code list_ec;
  const std::uintmax_t list_bytes = std::filesystem::file_size(list_path, list_ec);
  std::ifstream list(list_path);
  if (list_ec || !list) no_page(web_dir, std::string(kServedList) + " is missing or unreadable");
  if (list_bytes > kMaxServedFiles * (kMaxServedPath + 1))
    no_page(web_dir, std::string(kServedList) + " is too long to be a list of the page's files");
  std::map<std::string, File, std::less<>> files;
  std::uintmax_t bytes = 0;
  std::string path;
  for (std::size_t line = 1; std::getline(list, path); ++line) {
    const std::string where = std::string(kServedList) + " line " + std::to_string(line);
    if (files.size() >= kMaxServedFiles)
      no_page(web_dir, where + ": more than " + std::to_string(kMaxServedFiles) + " files");
    const std::string_view type = served_type(path);
    if (type.empty()) {
      no_page(web_dir, where + ": '" + path.substr(0, kMaxServedPath) +
                           "' is not a relative path of an .html, .js or .css file");
    }
    const std::filesystem::path file = web_dir / path;
    std::error_code ec;
    const std::uintmax_t size = std::filesystem::file_size(file, ec);
    if (ec) no_page(web_dir, path + " (" + where + ") is missing or unreadable");
    if (size > kMaxServedBytes - bytes)
      no_page(web_dir,
              "more than " + std::to_string(kMaxServedBytes >> 20) + " MiB of files, at " + path);
    bytes += size;
    std::ifstream in(file, std::ios::binary);
    std::ostringstream body;
    if (!in || (size > 0 && !(body << in.rdbuf())))
      no_page(web_dir, path + " (" + where + ") is missing or unreadable");
    const std::string url = path == "index.html" ? "/" : "/" + path;
    if (!files.emplace(url, File{std::string(type), body.str()}).second)
      no_page(web_dir, where + ": " + path + " is named twice");
  }
  if (!list.eof()) no_page(web_dir, std::string(kServedList) + " is unreadable");
  if (!files.contains("/"))
    no_page(web_dir, std::string(kServedList) + " does not name index.html");
  return files;
}

}  // namespace

std::string describe(const ServerCounts& c) {
  return "stopped; pages " + std::to_string(c.pages_connected) + ", states sent " +
         std::to_string(c.states_sent) + ", dropped for slow pages " +
         std::to_string(c.states_dropped) + ", refused: frames " +
         std::to_string(c.frames_refused) + ", commands " + std::to_string(c.commands_refused) +
         ", connections " + std::to_string(c.connections_refused) + ", http " +
         std::to_string(c.http_refused) + "; foxglove clients " +
         std::to_string(c.foxglove_clients) + ", messages sent " + std::to_string(c.foxglove_sent) +
         ", dropped for slow clients " + std::to_string(c.foxglove_dropped);
}

class Page : public std::enable_shared_from_this<Page> {
 public:
  Page(ViewServer::Impl& impl, tcp::socket socket, std::uint64_t id)
      : impl_(impl), ws_(std::move(socket)), id_(id) {}

  void accept(http::request<http::string_body> request) {
    beast::get_lowest_layer(ws_).expires_never();
    // A state frame's last partial segment must not wait for the page's ACK of the one before
    // (Nagle's algorithm against the receiver's delayed ACK: up to 40 ms on Linux).
    beast::error_code ignored;
    beast::get_lowest_layer(ws_).socket().set_option(tcp::no_delay(true), ignored);
    ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
    ws_.read_message_max(kMaxCommandBytes);
    // One WebSocket frame per message, written at once: Beast's default splits a message into
    // frames of its 4 KB write buffer, each its own write (and TCP segment, with TCP_NODELAY) and
    // each a separate chunk for the browser to forward to the page: 80 of them for a 10^4-body
    // pose frame (bench/notes/view-bench.md).
    ws_.auto_fragment(false);
    ws_.async_accept(request, [self = shared_from_this()](beast::error_code ec) {
      if (ec) return self->fail();
      self->open_ = true;
      ++self->impl_.counts.pages_connected;
      self->send_text(std::make_shared<const std::string>(
          hello_json(self->impl_.options.read_only, self->id_, self->impl_.options.playback)));
      if (self->impl_.greeting)
        for (Bytes& b : self->impl_.greeting())
          self->send_text(std::move(b));
      self->read();
    });
  }

  void send_text(Bytes text) {
    if (closed_) return;
    if (texts_.size() >= ViewServer::kMaxQueuedTexts) {
      texts_.pop_front();
      ++impl_.counts.texts_dropped;
    }
    texts_.push_back(std::move(text));
    write_next();
  }

  void send_state(Bytes frame) {
    if (closed_ || !open_) return;
    if (state_) ++impl_.counts.states_dropped;
    state_ = std::move(frame);
    write_next();
  }

  void close() {
    closed_ = true;
    beast::error_code ec;
    beast::get_lowest_layer(ws_).socket().close(ec);
  }

 private:
  void read() {
    ws_.async_read(in_, [self = shared_from_this()](beast::error_code ec, std::size_t) {
      if (ec) {
        if (ec == websocket::error::message_too_big) ++self->impl_.counts.frames_refused;
        return self->fail();
      }
      self->on_frame();
    });
  }

  void on_frame() {
    const bool text = ws_.got_text();
    const std::string frame = beast::buffers_to_string(in_.data());
    in_.consume(in_.size());
    if (!text) {
      refuse("binary frames are not accepted");
    } else if (frame == kAckCommand) {
      if (!unacked_.empty()) {  // (more acks than states: ignored)
        unacked_bytes_ -= unacked_.front();
        unacked_.pop_front();
      }
      write_next();
    } else {
      auto parsed = parse_command(frame);
      if (auto* error = std::get_if<std::string>(&parsed)) {
        refuse(*error);
      } else {
        const PageCommand& c = std::get<PageCommand>(parsed);
        const std::string wrong_mode = refusal_in_mode(c, impl_.options.playback);
        if (!wrong_mode.empty()) {  // a live command while playing a recording, or the reverse
          ++impl_.counts.commands_refused;
          send_text(std::make_shared<const std::string>(
              reply_json(c.id, op_name(c.op), false, "refused", 0, wrong_mode)));
        } else if (impl_.options.read_only && c.op != Op::kWatch) {  // watch: what it sees
          ++impl_.counts.commands_refused;
          send_text(std::make_shared<const std::string>(
              reply_json(c.id, op_name(c.op), false, "refused", 0, "rigid-view runs --read-only")));
        } else if (impl_.on_command) {
          std::weak_ptr<Page> weak = shared_from_this();
          net::io_context& ioc = impl_.ioc;
          impl_.on_command(id_, c, [weak, &ioc](Bytes reply) {
            net::post(ioc, [weak, reply = std::move(reply)]() mutable {
              if (auto page = weak.lock()) page->send_text(std::move(reply));
            });
          });
        }
      }
    }
    if (bad_frames_ > ViewServer::kMaxBadFrames) {
      ws_.async_close(websocket::close_code::policy_error,
                      [self = shared_from_this()](beast::error_code) { self->fail(); });
      return;
    }
    read();
  }

  void refuse(const std::string& why) {
    ++bad_frames_;
    ++impl_.counts.frames_refused;
    send_text(std::make_shared<const std::string>(error_json(why)));
  }

  void write_next() {
    if (writing_ || closed_ || !open_) return;
    Bytes next;
    bool text = false;
    if (!texts_.empty()) {
      next = std::move(texts_.front());
      texts_.pop_front();
      text = true;
    } else if (state_ && (unacked_.empty() ||
                          (unacked_.size() < ViewServer::kMaxUnackedStates &&
                           unacked_bytes_ + state_->size() <= ViewServer::kMaxUnackedBytes))) {
      next = std::move(state_);
      state_.reset();
      unacked_.push_back(next->size());
      unacked_bytes_ += next->size();
    } else {
      return;
    }
    writing_ = true;
    ws_.text(text);
    ws_.async_write(net::buffer(*next),
                    [self = shared_from_this(), next, text](beast::error_code ec, std::size_t) {
                      self->writing_ = false;
                      if (ec) return self->fail();
                      if (!text) ++self->impl_.counts.states_sent;
                      self->write_next();
                    });
  }

  void fail() {
    if (!closed_) close();
    texts_.clear();
    state_.reset();
    impl_.pages.erase(shared_from_this());
  }

  ViewServer::Impl& impl_;
  websocket::stream<beast::tcp_stream> ws_;
  beast::flat_buffer in_;
  std::uint64_t id_;
  std::deque<Bytes> texts_;
  Bytes state_;
  bool writing_ = false;
  std::deque<std::size_t> unacked_;  // sizes of the state frames written and not yet acknowledged
  std::size_t unacked_bytes_ = 0;
  bool open_ = false;
  bool closed_ = false;
  std::size_t bad_frames_ = 0;
};

namespace {

class HttpSession : public std::enable_shared_from_this<HttpSession> {
 public:
  HttpSession(ViewServer::Impl& impl, tcp::socket socket)
      : impl_(impl), stream_(std::move(socket)), buffer_(16 * 1024), count_(impl.http_sessions) {
    ++*count_;
  }
  ~HttpSession() { --*count_; }

  void run() {
    parser_.emplace();
    parser_->header_limit(8 * 1024);
    parser_->body_limit(1024);
    stream_.expires_after(10s);
    http::async_read(
        stream_, buffer_, *parser_,
        [self = shared_from_this()](beast::error_code ec, std::size_t) { self->on_read(ec); });
  }

 private:
  void on_read(beast::error_code ec) {
    if (ec) {
      if (ec != http::error::end_of_stream) ++impl_.counts.http_refused;
      return;
    }
    http::request<http::string_body> req = parser_->release();
    std::string_view target(req.target().data(), req.target().size());
    if (const auto q = target.find('?'); q != std::string_view::npos) target = target.substr(0, q);
    if (websocket::is_upgrade(req)) {
      const std::string_view origin(req[http::field::origin].data(),
                                    req[http::field::origin].size());
      const std::string_view host(req[http::field::host].data(), req[http::field::host].size());
      const bool same_origin = origin.empty() || origin == "http://" + std::string(host);
      if (offers_foxglove(req)) return foxglove(std::move(req), target, origin, same_origin);
      if (target != "/ws") return refuse(http::status::not_found, "no WebSocket here: use /ws");
      if (!same_origin) {
        ++impl_.counts.connections_refused;
        return refuse(http::status::forbidden, "a page from another origin may not connect");
      }
      if (impl_.connections() >= impl_.options.max_pages) {
        ++impl_.counts.connections_refused;
        return refuse(http::status::service_unavailable, "too many pages connected");
      }
      auto page = std::make_shared<Page>(impl_, stream_.release_socket(), impl_.next_page++);
      impl_.pages.insert(page);
      page->accept(std::move(req));
      return;
    }
    if (req.method() != http::verb::get && req.method() != http::verb::head)
      return refuse(http::status::method_not_allowed, "only GET");
    const auto it = impl_.files.find(target);
    if (it == impl_.files.end()) return refuse(http::status::not_found, "not found");
    respond(http::status::ok, it->second.type, it->second.body, req.method() == http::verb::head);
  }

  // Whether the client asks for the Foxglove WebSocket protocol (Sec-WebSocket-Protocol: a list
  // of tokens separated by commas).
  static bool offers_foxglove(const http::request<http::string_body>& req) {
    std::string_view offered(req[http::field::sec_websocket_protocol].data(),
                             req[http::field::sec_websocket_protocol].size());
    while (!offered.empty()) {
      const std::size_t comma = std::min(offered.find(','), offered.size());
      std::string_view token = offered.substr(0, comma);
      while (!token.empty() && (token.front() == ' ' || token.front() == '\t'))
        token.remove_prefix(1);
      while (!token.empty() && (token.back() == ' ' || token.back() == '\t'))
        token.remove_suffix(1);
      if (token == foxglove::kSubprotocol) return true;
      offered.remove_prefix(std::min(comma + 1, offered.size()));
    }
    return false;
  }

  // A Foxglove client (docs/foxglove.md): at / or /ws, from no origin, the page's, or one that
  // --foxglove-origin names; counted with the pages against their limit.
  void foxglove(http::request<http::string_body> req, std::string_view target,
                std::string_view origin, bool same_origin) {
    if (target != "/" && target != "/ws")
      return refuse(http::status::not_found, "no Foxglove WebSocket here: use / or /ws");
    if (impl_.options.playback || !impl_.foxglove_latest) {
      ++impl_.counts.connections_refused;
      return refuse(http::status::not_implemented,
                    "rigid-view FILE serves its page only: open rigid-record export --mcap's file "
                    "in Foxglove instead");
    }
    const auto& allowed = impl_.options.foxglove_origins;
    if (!same_origin && std::find(allowed.begin(), allowed.end(), origin) == allowed.end()) {
      ++impl_.counts.connections_refused;
      // Said once per origin (the first few): the value --foxglove-origin needs to admit an app.
      std::string shown(origin.substr(0, 200));
      for (char& ch : shown)
        if (ch < ' ' || ch > '~') ch = '?';
      if (impl_.refused_origins.size() < 8 && impl_.refused_origins.insert(shown).second) {
        std::cerr << "rigid-view: refused a Foxglove client from origin '" << shown
                  << "' (rigid-view --foxglove-origin '" << shown << "' admits it)\n";
      }
      return refuse(http::status::forbidden,
                    "a Foxglove client from origin '" + std::string(origin.substr(0, 200)) +
                        "' may not connect (rigid-view --foxglove-origin '" +
                        std::string(origin.substr(0, 200)) + "' admits it)");
    }
    if (impl_.connections() >= impl_.options.max_pages) {
      ++impl_.counts.connections_refused;
      return refuse(http::status::service_unavailable, "too many pages connected");
    }
    auto client =
        std::make_shared<FoxgloveConnection>(impl_, stream_.release_socket(), impl_.next_page++);
    impl_.foxglove_clients.insert(client);
    client->accept(std::move(req));
  }

  void refuse(http::status status, std::string_view why) {
    ++impl_.counts.http_refused;
    respond(status, "text/plain; charset=utf-8", std::string(why) + "\n", false);
  }

  void respond(http::status status, const std::string& type, const std::string& body, bool head) {
    res_.result(status);
    res_.version(11);
    res_.set(http::field::server, "rigid-view");
    res_.set(http::field::content_type, type);
    res_.set(http::field::cache_control, "no-store");
    res_.set("X-Content-Type-Options", "nosniff");
    res_.keep_alive(false);
    res_.body() = head ? std::string() : body;
    res_.prepare_payload();
    if (head) res_.content_length(body.size());
    http::async_write(stream_, res_, [self = shared_from_this()](beast::error_code, std::size_t) {
      beast::error_code ignored;
      self->stream_.socket().shutdown(tcp::socket::shutdown_send, ignored);
    });
  }

  ViewServer::Impl& impl_;
  beast::tcp_stream stream_;
  beast::flat_buffer buffer_;
  std::optional<http::request_parser<http::string_body>> parser_;
  http::response<http::string_body> res_;
  std::shared_ptr<std::size_t> count_;
};

}  // namespace

void ViewServer::Impl::accept() {
  acceptor.async_accept(ioc, [this](beast::error_code ec, tcp::socket socket) {
    if (ec == net::error::operation_aborted || !acceptor.is_open()) return;
    if (!ec) {
      if (*http_sessions >= kMaxHttpSessions) {
        ++counts.connections_refused;
        beast::error_code ignored;
        socket.close(ignored);
      } else {
        std::make_shared<HttpSession>(*this, std::move(socket))->run();
      }
    }
    accept();
  });
}

ViewServer::ViewServer(const ServerOptions& options, CommandHandler on_command, Greeting greeting,
                       FoxgloveLatest foxglove_latest)
    : impl_(std::make_unique<Impl>()) {
  impl_->options = options;
  impl_->on_command = std::move(on_command);
  impl_->greeting = std::move(greeting);
  impl_->foxglove_latest = std::move(foxglove_latest);
  // Foxglove's serverInfo sessionId: tells a client whether it reconnected to the same server.
  impl_->session_id = std::to_string(std::chrono::system_clock::now().time_since_epoch() /
                                     std::chrono::nanoseconds(1));
  impl_->files = read_page(options.web_dir);
  beast::error_code ec;
  auto address = net::ip::make_address(options.host, ec);
  if (ec) {
    // A host name: its first IPv4 address (what a browser given the name reaches too: it falls
    // back from IPv6), else its first address.
    tcp::resolver resolver(impl_->ioc);
    const auto found = resolver.resolve(options.host, std::to_string(options.port), ec);
    if (ec || found.empty()) {
      throw std::runtime_error("--listen: cannot resolve " + options.host + ": " +
                               (ec ? ec.message() : std::string("no address")));
    }
    address = found.begin()->endpoint().address();
    for (const auto& entry : found) {
      if (entry.endpoint().address().is_v4()) {
        address = entry.endpoint().address();
        break;
      }
    }
  }
  const tcp::endpoint endpoint(address, options.port);
  auto& a = impl_->acceptor;
  if (a.open(endpoint.protocol(), ec); !ec)
    if (a.set_option(net::socket_base::reuse_address(true), ec); !ec)
      if (a.bind(endpoint, ec); !ec) a.listen(net::socket_base::max_listen_connections, ec);
  if (ec) {
    throw std::runtime_error("cannot listen on " + options.host + ":" +
                             std::to_string(options.port) + ": " + ec.message());
  }
}

ViewServer::~ViewServer() {
  stop();
}

std::uint16_t ViewServer::port() const {
  return impl_->acceptor.local_endpoint().port();
}

std::string ViewServer::address() const {
  return impl_->acceptor.local_endpoint().address().to_string();
}

bool ViewServer::listens_beyond_host() const {
  return !impl_->acceptor.local_endpoint().address().is_loopback();
}

void ViewServer::start() {
  impl_->accept();
  impl_->thread = std::thread([this] { impl_->ioc.run(); });
}

void ViewServer::stop() {
  if (!impl_->thread.joinable()) return;
  net::post(impl_->ioc, [impl = impl_.get()] {
    beast::error_code ignored;
    impl->acceptor.close(ignored);
    for (const auto& page : impl->pages)
      page->close();
    impl->pages.clear();
    for (const auto& client : impl->foxglove_clients)
      client->close();
    impl->foxglove_clients.clear();
    impl->ioc.stop();
  });
  impl_->thread.join();
}

void ViewServer::broadcast_state(Bytes frame) {
  net::post(impl_->ioc, [impl = impl_.get(), frame = std::move(frame)] {
    for (const auto& page : impl->pages)
      page->send_state(frame);
  });
}

void ViewServer::broadcast_text(Bytes text) {
  net::post(impl_->ioc, [impl = impl_.get(), text = std::move(text)] {
    for (const auto& page : impl->pages)
      page->send_text(text);
  });
}

bool ViewServer::foxglove_subscribed(foxglove::Channel channel) const {
  return impl_->subscribers[foxglove::index_of(channel)].load(std::memory_order_relaxed) > 0;
}

void ViewServer::broadcast_foxglove(foxglove::Channel channel, FoxgloveMessage message) {
  net::post(impl_->ioc, [impl = impl_.get(), channel, message = std::move(message)] {
    for (const auto& client : impl->foxglove_clients)
      client->send(channel, message);
  });
}

void ViewServer::set_body_ids(std::map<std::string, std::int32_t, std::less<>> ids) {
  net::post(impl_->ioc, [impl = impl_.get(), ids = std::move(ids)]() mutable {
    impl->body_ids = std::move(ids);
  });
}

const ServerCounts& ViewServer::counts() const {
  return impl_->counts;
}

}  // namespace rigid::view
