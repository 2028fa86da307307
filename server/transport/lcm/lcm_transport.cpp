#include "transport/lcm/lcm_transport.hpp"

#include <poll.h>
#include <sys/eventfd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <mutex>
#include <span>
#include <thread>
#include <type_traits>
#include <vector>

#include "transport/lcm/lcm_codec.hpp"
#include "transport/lcm/lcm_command_socket.hpp"
#include "transport/lcm/lcm_handle.hpp"
#include "transport/message_topic.hpp"
#include "transport/traffic_counter.hpp"
#include "util/thread_name.hpp"

namespace rigid::transport::lcm {
namespace {

void deliver(Receiver& receiver, const StateFrame& message) {
  receiver.on_state(message);
}
void deliver(Receiver& receiver, const WrenchCommand& message) {
  receiver.on_wrench(message, Origin{});
}
void deliver(Receiver& receiver, const ControlCommand& message) {
  receiver.on_control(message, Origin{});
}
void deliver(Receiver& receiver, const EditCommand& message) {
  receiver.on_edit(message, Origin{});
}

// The command socket wants a receive buffer that holds a burst (it also sees every state the
// server multicasts on the same group, fragments that it drops).
std::string with_receive_buffer(const std::string& url) {
  if (url.find("recv_buf_size=") != std::string::npos) return url;
  return url + (url.find('?') == std::string::npos ? "?" : "&") + "recv_buf_size=4194304";
}
void deliver(Receiver& receiver, const ControlReply& message) {
  receiver.on_control_reply(message);
}
void deliver(Receiver& receiver, const StatsReport& message) {
  receiver.on_stats(message);
}
void deliver(Receiver& receiver, const SceneDescription& message) {
  receiver.on_scene(message);
}
void deliver(Receiver& receiver, const AcceptedCommand& message) {
  receiver.on_accepted(message);
}
void deliver(Receiver& receiver, const ContactEvents& message) {
  receiver.on_contacts(message);
}

// What the receive thread needs to turn a payload into a callback.
struct Intake {
  Codec& codec;
  Receiver& receiver;
  TrafficCounter& counter;
};

// One subscribed channel and the plain message its payloads are decoded into (reused).
class Inbox {
 public:
  virtual ~Inbox() = default;
  virtual void handle(std::span<const std::uint8_t> payload) = 0;

  // lcm's C callback; `user` is the Inbox.
  static void on_message(const lcm_recv_buf_t* buffer, const char* /*channel*/, void* user) {
    static_cast<Inbox*>(user)->handle(
        {static_cast<const std::uint8_t*>(buffer->data), buffer->data_size});
  }
};

// liblcm's receive thread queues at most 30 messages per subscription for lcm_handle (the default
// of lcm_subscription_set_queue_capacity) and drops the rest. That is 30 ms of states at 1 kHz, and
// a lockstep step request sends its states as fast as the bus takes them: a subscriber whose
// handler thread loses the CPU for a moment loses states (bench/notes/transport.md). A client's
// state subscription holds up to kStateQueueBytes of states instead, at most kStateQueueMessages of
// them: sized to the states that arrive, so a large scene's queue is no larger in bytes.
inline constexpr std::size_t kStateQueueBytes = std::size_t{64} << 20;
inline constexpr int kStateQueueMessages = 1024;
inline constexpr int kLcmDefaultQueueMessages = 30;

int state_queue_capacity(std::size_t state_bytes) {
  const std::size_t fit = kStateQueueBytes / std::max<std::size_t>(state_bytes, 1);
  return static_cast<int>(
      std::clamp<std::size_t>(fit, kLcmDefaultQueueMessages, kStateQueueMessages));
}

template <class Plain>
class TypedInbox final : public Inbox {
 public:
  explicit TypedInbox(Intake intake) : intake_(intake) {}

  // The subscription this inbox is called for (set once, after lcm_subscribe).
  void set_subscription(lcm_subscription_t* subscription) {
    subscription_ = subscription;
    if constexpr (std::is_same_v<Plain, StateFrame>) {
      capacity_ = kStateQueueMessages;
      lcm_subscription_set_queue_capacity(subscription_, capacity_);
    }
  }

  void handle(std::span<const std::uint8_t> payload) override {
    if constexpr (std::is_same_v<Plain, StateFrame>) {
      // liblcm's lock is recursive: this thread may change the queue it is called from.
      const int wanted = state_queue_capacity(payload.size());
      if (wanted != capacity_ && subscription_ != nullptr) {
        capacity_ = wanted;
        lcm_subscription_set_queue_capacity(subscription_, capacity_);
      }
    }
    const DecodeStatus status = intake_.codec.decode(payload, message_);
    if (status == DecodeStatus::kOk) {
      intake_.counter.received();
      deliver(intake_.receiver, message_);
    } else {
      intake_.counter.decode_failed();
      intake_.receiver.on_decode_error({Bus::kLcm, TopicOf<Plain>::value, status, payload.size()});
    }
  }

 private:
  Intake intake_;
  Plain message_;
  lcm_subscription_t* subscription_ = nullptr;
  int capacity_ = kLcmDefaultQueueMessages;
};

class LcmTransport final : public Transport {
 public:
  LcmTransport(const Options& options, Receiver& receiver)
      : role_(options.role), channels_(lcm_channel_names(options.prefix)) {
    if (!is_valid_prefix(options.prefix)) {
      throw TransportError("LCM: invalid prefix '" + options.prefix +
                           "' (letters, digits and '_' only)");
    }
    lcm_.reset(lcm_create(options.url.c_str()));
    if (!lcm_) {
      throw TransportError("LCM: cannot open " + options.url +
                           " (udpm on this host needs a multicast route on lo: run "
                           "scripts/net-setup as root, or 'ip route replace 224.0.0.0/4 dev lo')");
    }
    wake_ = FileDescriptor(::eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK));
    if (wake_.get() < 0) {
      throw TransportError(std::string("LCM: cannot create an eventfd: ") + std::strerror(errno));
    }
    const Intake intake{codec_, receiver, counter_};
    if (role_ == Role::kServer) {
      // The server receives commands on its own bounded socket, never through liblcm, whose
      // reassembly of fragmented messages holds up to 256 MB per sender (lcm_command_socket.hpp).
      // liblcm then never opens a receive socket in this process: it only publishes.
      commands_ = std::make_unique<CommandSocket>(
          with_receive_buffer(options.url),
          std::vector<std::string>{channels_[index_of(Topic::kWrench)],
                                   channels_[index_of(Topic::kControl)],
                                   channels_[index_of(Topic::kEdit)]});
      thread_ = std::thread([this, &receiver] { receive_commands(receiver); });
      util::name_thread(thread_, "rigid-lcm-in");
      return;
    }
    subscribe<StateFrame>(intake);
    subscribe<WrenchCommand>(intake);
    subscribe<ControlCommand>(intake);
    subscribe<EditCommand>(intake);
    subscribe<ControlReply>(intake);
    subscribe<StatsReport>(intake);
    subscribe<SceneDescription>(intake);
    subscribe<AcceptedCommand>(intake);
    subscribe<ContactEvents>(intake);
    thread_ = std::thread([this] { receive_loop(); });
    util::name_thread(thread_, "rigid-lcm-in");
  }

  ~LcmTransport() override {
    // Cannot fail: the counter is far from overflowing after one increment.
    eventfd_write(wake_.get(), 1);
    if (thread_.joinable()) thread_.join();
  }

  LcmTransport(const LcmTransport&) = delete;
  LcmTransport& operator=(const LcmTransport&) = delete;

  Bus bus() const override { return Bus::kLcm; }
  Role role() const override { return role_; }

  PublishResult publish(const StateFrame& m) override { return send(m); }
  PublishResult publish(const StatsReport& m) override { return send(m); }
  PublishResult publish(const SceneDescription& m) override {
    constexpr std::size_t i = index_of(Topic::kScene);
    if (!publishes(role_, Topic::kScene)) return PublishResult::kWrongRole;
    const std::lock_guard lock(send_mutex_[i]);
    // A refused scene leaves the codec's bytes, and so the scene republished, as they were.
    const std::span<const std::uint8_t> payload = codec_.encode(m);
    if (payload.empty()) return PublishResult::kInvalid;
    scene_payload_ = payload;  // valid until the next scene is encoded, under this lock
    return send_payload(i, scene_payload_);
  }
  PublishResult republish_scene() override {
    constexpr std::size_t i = index_of(Topic::kScene);
    if (!publishes(role_, Topic::kScene)) return PublishResult::kWrongRole;
    const std::lock_guard lock(send_mutex_[i]);
    if (scene_payload_.empty()) return PublishResult::kInvalid;
    return send_payload(i, scene_payload_);
  }
  PublishResult publish(const ControlReply& m) override { return send(m); }
  PublishResult publish(const WrenchCommand& m) override { return send(m); }
  PublishResult publish(const ControlCommand& m) override { return send(m); }
  PublishResult publish(const EditCommand& m) override { return send(m); }
  PublishResult publish(const AcceptedCommand& m) override { return send(m); }
  PublishResult publish(const ContactEvents& m) override { return send(m); }

  TransportCounts counts() const override { return counter_.snapshot(); }

 private:
  template <class Plain>
  void subscribe(const Intake& intake) {
    constexpr Topic topic = TopicOf<Plain>::value;
    if (publishes(role_, topic)) return;
    auto inbox = std::make_unique<TypedInbox<Plain>>(intake);
    TypedInbox<Plain>& typed = *inbox;
    inboxes_.push_back(std::move(inbox));
    const std::string& channel = channels_[index_of(topic)];
    lcm_subscription_t* subscription =
        lcm_subscribe(lcm_.get(), channel.c_str(), &Inbox::on_message, &typed);
    if (subscription == nullptr) throw TransportError("LCM: cannot subscribe to " + channel);
    typed.set_subscription(subscription);
  }

  template <class Plain>
  PublishResult send(const Plain& message) {
    constexpr std::size_t i = index_of(TopicOf<Plain>::value);
    if (!publishes(role_, TopicOf<Plain>::value)) return PublishResult::kWrongRole;
    const std::lock_guard lock(send_mutex_[i]);
    const std::span<const std::uint8_t> payload = codec_.encode(message);
    if (payload.empty()) return PublishResult::kInvalid;
    return send_payload(i, payload);
  }

  // Holding send_mutex_[i].
  PublishResult send_payload(std::size_t i, std::span<const std::uint8_t> payload) {
    // lcm_publish returns 0 even when receivers drop the message: loss is only seen by them.
    const int result = lcm_publish(lcm_.get(), channels_[i].c_str(), payload.data(),
                                   static_cast<unsigned int>(payload.size()));
    return counter_.count(result == 0 ? PublishResult::kOk : PublishResult::kFailed);
  }

  // Server role: each datagram on a command channel is decoded and delivered with its sender's
  // session (its UDP address and port).
  void receive_commands(Receiver& receiver) {
    std::array<pollfd, 2> fds{};
    fds[0] = {commands_->fd(), POLLIN, 0};
    fds[1] = {wake_.get(), POLLIN, 0};
    const std::string& wrench_channel = channels_[index_of(Topic::kWrench)];
    const std::string& edit_channel = channels_[index_of(Topic::kEdit)];
    const auto topic_of = [&](std::string_view channel) {
      return channel == wrench_channel ? Topic::kWrench
             : channel == edit_channel ? Topic::kEdit
                                       : Topic::kControl;
    };
    for (;;) {
      if (::poll(fds.data(), fds.size(), -1) < 0) {
        if (errno == EINTR) continue;
        return;
      }
      if (fds[1].revents != 0) return;
      if ((fds[0].revents & POLLIN) == 0) continue;
      commands_->receive(
          [&](std::string_view channel, std::span<const std::uint8_t> payload,
              std::uint64_t session) {
            Origin origin;
            origin.session = session;
            const Topic topic = topic_of(channel);
            const DecodeStatus status = topic == Topic::kWrench ? codec_.decode(payload, wrench_)
                                        : topic == Topic::kEdit ? codec_.decode(payload, edit_)
                                                                : codec_.decode(payload, control_);
            if (status != DecodeStatus::kOk) {
              counter_.decode_failed();
              receiver.on_decode_error({Bus::kLcm, topic, status, payload.size()});
              return;
            }
            counter_.received();
            if (topic == Topic::kWrench) {
              receiver.on_wrench(wrench_, origin);
            } else if (topic == Topic::kEdit) {
              receiver.on_edit(edit_, origin);
            } else {
              receiver.on_control(control_, origin);
            }
          },
          [&](const Rejected& rejected) {
            // A command too large for one datagram (its first fragment on a command channel) or
            // a datagram that is not LCM at all: counted, never reassembled.
            if (rejected.reason == Rejection::kFragment && rejected.channel.empty()) return;
            counter_.decode_failed();
            receiver.on_decode_error(
                {Bus::kLcm, topic_of(rejected.channel), DecodeStatus::kMalformed, rejected.bytes});
          });
    }
  }

  void receive_loop() {
    std::array<pollfd, 2> fds{};
    fds[0] = {lcm_get_fileno(lcm_.get()), POLLIN, 0};
    fds[1] = {wake_.get(), POLLIN, 0};
    for (;;) {
      if (::poll(fds.data(), fds.size(), -1) < 0) {
        if (errno == EINTR) continue;
        return;
      }
      if (fds[1].revents != 0) return;
      // LCM's descriptor is readable once a whole message is queued, so this does not block.
      if ((fds[0].revents & POLLIN) != 0 && lcm_handle(lcm_.get()) != 0) return;
    }
  }

  const Role role_;
  const TopicNames channels_;
  TrafficCounter counter_;
  Codec codec_;
  std::array<std::mutex, kAllTopics.size()> send_mutex_;  // guards the codec's encode buffers
  // The last scene published, in the codec's buffer (under the scene's send_mutex_): republished.
  std::span<const std::uint8_t> scene_payload_;
  std::vector<std::unique_ptr<Inbox>> inboxes_;  // outlive lcm_, which calls into them
  std::unique_ptr<CommandSocket> commands_;      // server role
  WrenchCommand wrench_;                         // decoded commands, reused
  ControlCommand control_;
  EditCommand edit_;
  LcmHandle lcm_;
  FileDescriptor wake_;
  std::thread thread_;
};

}  // namespace

std::unique_ptr<Transport> make_transport(const Options& options, Receiver& receiver) {
  return std::make_unique<LcmTransport>(options, receiver);
}

}  // namespace rigid::transport::lcm
