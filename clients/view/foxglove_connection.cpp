#include "foxglove_connection.hpp"

#include <chrono>

#include "server_impl.hpp"

namespace rigid::view {
namespace {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using tcp = net::ip::tcp;

}  // namespace

FoxgloveConnection::FoxgloveConnection(ViewServer::Impl& impl, tcp::socket socket, std::uint64_t id)
    : impl_(impl), ws_(std::move(socket)), id_(id) {}

void FoxgloveConnection::accept(http::request<http::string_body> request) {
  beast::get_lowest_layer(ws_).expires_never();
  // A message's last partial segment must not wait for the client's ACK of the one before
  // (Nagle's algorithm against delayed ACKs), as for the page.
  beast::error_code ignored;
  beast::get_lowest_layer(ws_).socket().set_option(tcp::no_delay(true), ignored);
  ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
  ws_.set_option(websocket::stream_base::decorator([](websocket::response_type& response) {
    response.set(http::field::sec_websocket_protocol,
                 beast::string_view(foxglove::kSubprotocol.data(), foxglove::kSubprotocol.size()));
    response.set(http::field::server, "rigid-view");
  }));
  ws_.read_message_max(foxglove::kMaxClientText);
  ws_.auto_fragment(false);  // one WebSocket frame per message, written at once (server.cpp)
  ws_.async_accept(request, [self = shared_from_this()](beast::error_code ec) {
    if (ec) return self->fail();
    self->open_ = true;
    ++self->impl_.counts.foxglove_clients;
    self->send_text(
        foxglove::server_info_json(!self->impl_.options.read_only, self->impl_.session_id));
    self->texts_.push_back(std::make_shared<const std::string>(foxglove::advertise_json()));
    self->write_next();
    self->read();
  });
}

void FoxgloveConnection::send(foxglove::Channel channel, const FoxgloveMessage& message) {
  const std::size_t k = foxglove::index_of(channel);
  if (closed_ || !open_ || !subscription_[k] || !message.payload) return;
  if (slots_[k]) ++impl_.counts.foxglove_dropped;
  slots_[k] = message;
  write_next();
}

void FoxgloveConnection::close() {
  closed_ = true;
  unsubscribe_all();
  beast::error_code ec;
  beast::get_lowest_layer(ws_).socket().close(ec);
}

void FoxgloveConnection::read() {
  ws_.async_read(in_, [self = shared_from_this()](beast::error_code ec, std::size_t) {
    if (ec) {
      if (ec == websocket::error::message_too_big) ++self->impl_.counts.frames_refused;
      return self->fail();
    }
    self->on_frame();
  });
}

void FoxgloveConnection::on_frame() {
  const bool text = ws_.got_text();
  const std::string frame = beast::buffers_to_string(in_.data());
  in_.consume(in_.size());
  if (text) {
    on_text(frame);
  } else {
    on_binary(frame);
  }
  if (bad_frames_ > ViewServer::kMaxBadFrames) {
    ws_.async_close(websocket::close_code::policy_error,
                    [self = shared_from_this()](beast::error_code) { self->fail(); });
    return;
  }
  read();
}

void FoxgloveConnection::on_text(const std::string& text) {
  auto parsed = foxglove::parse_client_text(text);
  if (auto* error = std::get_if<std::string>(&parsed)) return refuse(*error);
  auto& message = std::get<foxglove::ClientText>(parsed);
  if (auto* s = std::get_if<foxglove::Subscribe>(&message)) {
    for (const auto& [id, channel] : s->subscriptions) {
      if (channel < 1 || channel > foxglove::kChannelCount) {
        refuse("subscribe: no channel " + std::to_string(channel));
        continue;
      }
      bool taken = false;
      for (const auto& sub : subscription_)
        taken = taken || (sub && *sub == id);
      const std::size_t k = channel - 1;
      if (taken || subscription_[k]) {
        refuse("subscribe: subscription id " + std::to_string(id) + " or channel " +
               std::to_string(channel) + " already subscribed");
        continue;
      }
      subscription_[k] = id;
      ++impl_.subscribers[k];
      // The newest message at once: a paused simulation sends no new state, and the scene only
      // when it changes.
      if (impl_.foxglove_latest)
        send(static_cast<foxglove::Channel>(channel),
             impl_.foxglove_latest(static_cast<foxglove::Channel>(channel)));
    }
  } else if (auto* u = std::get_if<foxglove::Unsubscribe>(&message)) {
    for (const std::uint32_t id : u->ids) {
      bool found = false;
      for (std::size_t k = 0; k < foxglove::kChannelCount; ++k) {
        if (subscription_[k] && *subscription_[k] == id) {
          subscription_[k].reset();
          slots_[k].reset();
          --impl_.subscribers[k];
          found = true;
        }
      }
      if (!found) refuse("unsubscribe: no subscription " + std::to_string(id));
    }
  } else if (auto* a = std::get_if<foxglove::ClientAdvertise>(&message)) {
    if (impl_.options.read_only) {
      ++impl_.counts.commands_refused;
      send_text(foxglove::status_json(2,
                                      "advertise: rigid-view runs --read-only: clients may "
                                      "not publish"));
      return;
    }
    for (const foxglove::ClientChannel& c : a->channels) {
      if (c.topic != foxglove::kPushTopic || c.encoding != foxglove::kPushEncoding) {
        refuse("advertise: " + c.topic.substr(0, 64) + " (" + c.encoding.substr(0, 16) +
               "): rigid-view takes only " + std::string(foxglove::kPushTopic) + " in json");
      } else if (client_channels_.size() >= foxglove::kMaxClientChannels &&
                 !client_channels_.contains(c.id)) {
        refuse("advertise: more than " + std::to_string(foxglove::kMaxClientChannels) +
               " client channels");
      } else {
        client_channels_[c.id] = true;
      }
    }
  } else if (auto* ua = std::get_if<foxglove::ClientUnadvertise>(&message)) {
    for (const std::uint32_t id : ua->ids)
      if (client_channels_.erase(id) == 0)
        refuse("unadvertise: no client channel " + std::to_string(id));
  }
}

void FoxgloveConnection::on_binary(const std::string& bytes) {
  auto parsed = foxglove::parse_client_binary(bytes);
  if (auto* error = std::get_if<std::string>(&parsed)) return refuse(*error);
  const foxglove::ClientData& d = std::get<foxglove::ClientData>(parsed);
  if (!client_channels_.contains(d.channel)) {
    return refuse("Client Message Data on channel " + std::to_string(d.channel) +
                  ", which this client did not advertise");
  }
  if (impl_.options.read_only) {  // (not advertised then: refused above; kept as a guard)
    ++impl_.counts.commands_refused;
    return send_text(foxglove::status_json(2, "push: rigid-view runs --read-only"));
  }
  auto push = foxglove::parse_push(d.payload);
  if (auto* error = std::get_if<std::string>(&push)) return refuse(*error);
  const foxglove::PushRequest& p = std::get<foxglove::PushRequest>(push);
  PageCommand c;
  c.op = Op::kPush;
  c.body = p.body;
  if (!p.body_name.empty()) {
    const auto it = impl_.body_ids.find(p.body_name);
    if (it == impl_.body_ids.end()) {
      ++impl_.counts.commands_refused;
      return send_text(foxglove::status_json(
          2, "push: no body named " + p.body_name.substr(0, 64) + " in rigidd's scene"));
    }
    c.body = it->second;
  }
  c.force = p.force;
  c.point = p.point;
  c.ttl = p.duration;
  if (const std::string wrong = refusal_in_mode(c, impl_.options.playback); !wrong.empty()) {
    ++impl_.counts.commands_refused;
    return send_text(foxglove::status_json(2, wrong));
  }
  if (impl_.on_command) impl_.on_command(id_, c, [](Bytes) {});  // a push has no answer
}

void FoxgloveConnection::refuse(const std::string& why) {
  ++bad_frames_;
  ++impl_.counts.frames_refused;
  send_text(foxglove::status_json(2, why));
}

void FoxgloveConnection::send_text(std::string text) {
  if (closed_) return;
  if (texts_.size() >= ViewServer::kMaxQueuedTexts) {
    texts_.pop_front();
    ++impl_.counts.texts_dropped;
  }
  texts_.push_back(std::make_shared<const std::string>(std::move(text)));
  write_next();
}

void FoxgloveConnection::write_next() {
  if (writing_ || closed_ || !open_) return;
  if (!texts_.empty()) {
    Bytes next = std::move(texts_.front());
    texts_.pop_front();
    writing_ = true;
    ws_.text(true);
    ws_.async_write(net::buffer(*next),
                    [self = shared_from_this(), next](beast::error_code ec, std::size_t) {
                      self->writing_ = false;
                      if (ec) return self->fail();
                      self->write_next();
                    });
    return;
  }
  for (std::size_t n = 0; n < foxglove::kChannelCount; ++n) {
    const std::size_t k = (next_slot_ + n) % foxglove::kChannelCount;
    if (!slots_[k] || !subscription_[k]) continue;
    FoxgloveMessage m = std::move(*slots_[k]);
    slots_[k].reset();
    next_slot_ = (k + 1) % foxglove::kChannelCount;
    header_ = foxglove::message_data_header(*subscription_[k], m.time_ns);
    writing_ = true;
    ws_.binary(true);
    const std::array<net::const_buffer, 2> buffers{net::buffer(header_), net::buffer(*m.payload)};
    ws_.async_write(buffers, [self = shared_from_this(), payload = m.payload](beast::error_code ec,
                                                                              std::size_t) {
      self->writing_ = false;
      if (ec) return self->fail();
      ++self->impl_.counts.foxglove_sent;
      self->write_next();
    });
    return;
  }
}

void FoxgloveConnection::unsubscribe_all() {
  for (std::size_t k = 0; k < foxglove::kChannelCount; ++k) {
    if (subscription_[k]) --impl_.subscribers[k];
    subscription_[k].reset();
    slots_[k].reset();
  }
}

void FoxgloveConnection::fail() {
  if (!closed_) close();
  texts_.clear();
  impl_.foxglove_clients.erase(shared_from_this());
}

}  // namespace rigid::view
