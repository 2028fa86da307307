#include "transport/dds/dds_transport.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <mutex>
#include <thread>
#include <vector>

#include "transport/dds/dds_convert.hpp"
#include "transport/dds/dds_entity.hpp"
#include "transport/dds/dds_qos.hpp"
#include "transport/message_topic.hpp"
#include "transport/traffic_counter.hpp"

namespace rigid::transport::dds {
namespace {

void deliver(Receiver& receiver, const StateFrame& message) {
  receiver.on_state(message);
}
void deliver(Receiver& receiver, const WrenchCommand& message) {
  receiver.on_wrench(message);
}
void deliver(Receiver& receiver, const ControlCommand& message) {
  receiver.on_control(message);
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

// A reader and what it takes samples into: the idlc sample (its sequences grow to the largest
// message seen, then are reused) and the plain message handed to the Receiver.
class Inbox {
 public:
  virtual ~Inbox() = default;
  // Takes the available samples, at most kMaxPerDrain, and hands each to the receiver.
  virtual void drain(Receiver& receiver, TrafficCounter& counter) = 0;
  // A reader still holding samples triggers the waitset again at once, and the readers take turns:
  // a reader flooded about as fast as it is drained (10^5 wrenches a second) cannot starve the
  // others (bench/flood measured a control request waiting 200 ms behind such a flood). At most
  // the commands' history depth per turn.
  static constexpr int kMaxPerDrain = 256;
  dds_entity_t condition() const { return condition_.get(); }

 protected:
  void open(dds_entity_t participant, dds_entity_t topic, const dds_qos_t* qos,
            const std::string& name) {
    reader_ = Entity(dds_create_reader(participant, topic, qos, nullptr), "reader for " + name);
    condition_ = Entity(dds_create_readcondition(reader_.get(), DDS_ANY_STATE),
                        "read condition for " + name);
  }
  Entity reader_;
  Entity condition_;  // declared after reader_: deleted before it
};

template <class Plain>
class TypedInbox final : public Inbox {
 public:
  TypedInbox(dds_entity_t participant, dds_entity_t topic, const dds_qos_t* qos,
             const std::string& name) {
    open(participant, topic, qos, name);
  }
  ~TypedInbox() override {
    dds_sample_free(&sample_, DdsTypeOf<Plain>::descriptor, DDS_FREE_CONTENTS);
  }
  TypedInbox(const TypedInbox&) = delete;
  TypedInbox& operator=(const TypedInbox&) = delete;

  void drain(Receiver& receiver, TrafficCounter& counter) override {
    // A non-null buffer makes dds_take copy into our sample instead of lending one.
    void* buffer[1] = {&sample_};
    dds_sample_info_t info;
    for (int n = 0; n < kMaxPerDrain && dds_take(reader_.get(), buffer, &info, 1, 1) > 0; ++n) {
      if (!info.valid_data) continue;  // a dispose or unregister notice, no data
      const DecodeStatus status = copy_from(sample_, message_);
      if (status == DecodeStatus::kOk) {
        counter.received();
        deliver(receiver, message_);
      } else {
        counter.decode_failed();
        receiver.on_decode_error({Bus::kDds, DdsTypeOf<Plain>::topic, status, 0});
      }
    }
  }

 private:
  typename DdsTypeOf<Plain>::type sample_{};
  Plain message_;
};

class DdsTransport final : public Transport {
 public:
  DdsTransport(const Options& options, Receiver& receiver)
      : role_(options.role), receiver_(receiver) {
    if (!is_valid_prefix(options.prefix)) {
      throw TransportError("DDS: invalid prefix '" + options.prefix +
                           "' (letters, digits and '_' only)");
    }
    participant_ = Entity(dds_create_participant(options.domain, nullptr, nullptr),
                          "participant on domain " + std::to_string(options.domain) +
                              " (is CYCLONEDDS_URI a readable config? scripts/net-setup prints "
                              "the loopback one)");
    waitset_ = Entity(dds_create_waitset(participant_.get()), "waitset");
    stop_ = Entity(dds_create_guardcondition(participant_.get()), "guard condition");
    check(dds_waitset_attach(waitset_.get(), stop_.get(), kStopToken), "attach guard condition");

    const TopicNames names = dds_topic_names(options.prefix);
    create<StateFrame>(names, options.reliable_state);
    create<WrenchCommand>(names, options.reliable_state);
    create<ControlCommand>(names, options.reliable_state);
    create<ControlReply>(names, options.reliable_state);
    create<StatsReport>(names, options.reliable_state);
    create<SceneDescription>(names, options.reliable_state);
    create<AcceptedCommand>(names, options.reliable_state);

    thread_ = std::thread([this] { receive_loop(); });
  }

  ~DdsTransport() override {
    dds_set_guardcondition(stop_.get(), true);
    if (thread_.joinable()) thread_.join();
  }

  DdsTransport(const DdsTransport&) = delete;
  DdsTransport& operator=(const DdsTransport&) = delete;

  Bus bus() const override { return Bus::kDds; }
  Role role() const override { return role_; }

  PublishResult publish(const StateFrame& m) override { return write(m); }
  PublishResult publish(const StatsReport& m) override { return write(m); }
  PublishResult publish(const SceneDescription& m) override { return write(m); }
  PublishResult publish(const ControlReply& m) override { return write(m); }
  PublishResult publish(const WrenchCommand& m) override { return write(m); }
  PublishResult publish(const ControlCommand& m) override { return write(m); }
  PublishResult publish(const AcceptedCommand& m) override { return write(m); }

  TransportCounts counts() const override { return counter_.snapshot(); }

 private:
  // The waitset token of the stop condition; readers use their index in inboxes_.
  static constexpr dds_attach_t kStopToken = -1;

  static void check(dds_return_t result, const std::string& what) {
    if (result < 0) throw TransportError("DDS: cannot " + what + ": " + dds_strretcode(result));
  }

  template <class Plain>
  void create(const TopicNames& names, bool reliable_state) {
    constexpr Topic topic = DdsTypeOf<Plain>::topic;
    const std::string& name = names[index_of(topic)];
    const Qos qos = topic_qos(topic, reliable_state);
    Entity& entity = topics_[index_of(topic)];
    entity = Entity(dds_create_topic(participant_.get(), DdsTypeOf<Plain>::descriptor, name.c_str(),
                                     qos.get(), nullptr),
                    "topic " + name);
    if (publishes(role_, topic)) {
      writers_[index_of(topic)] =
          Entity(dds_create_writer(participant_.get(), entity.get(), qos.get(), nullptr),
                 "writer for " + name);
    } else {
      inboxes_.push_back(
          std::make_unique<TypedInbox<Plain>>(participant_.get(), entity.get(), qos.get(), name));
      check(dds_waitset_attach(waitset_.get(), inboxes_.back()->condition(),
                               static_cast<dds_attach_t>(inboxes_.size() - 1)),
            "attach read condition for " + name);
    }
  }

  template <class Plain>
  PublishResult write(const Plain& message) {
    constexpr std::size_t i = index_of(DdsTypeOf<Plain>::topic);
    if (writers_[i].get() <= 0) return PublishResult::kWrongRole;
    const std::lock_guard lock(send_mutex_[i]);
    typename DdsTypeOf<Plain>::type sample{};
    if (!borrow(message, scratch_[i], sample)) return PublishResult::kInvalid;
    const dds_return_t result = dds_write(writers_[i].get(), &sample);
    return counter_.count(result == DDS_RETCODE_OK ? PublishResult::kOk : PublishResult::kFailed);
  }

  void receive_loop() {
    std::array<dds_attach_t, kAllTopics.size() + 1> triggered{};
    for (;;) {
      const dds_return_t n =
          dds_waitset_wait(waitset_.get(), triggered.data(), triggered.size(), DDS_INFINITY);
      if (n < 0) return;  // the waitset is gone: the transport is being destroyed
      const auto count = std::min(static_cast<std::size_t>(n), triggered.size());
      for (std::size_t k = 0; k < count; ++k) {
        const dds_attach_t token = triggered[k];
        if (token == kStopToken) return;
        inboxes_[static_cast<std::size_t>(token)]->drain(receiver_, counter_);
      }
    }
  }

  const Role role_;
  Receiver& receiver_;
  TrafficCounter counter_;
  // Declaration order is destruction order reversed: the participant goes last.
  Entity participant_;
  Entity waitset_;
  Entity stop_;
  std::array<Entity, kAllTopics.size()> topics_;
  std::array<Entity, kAllTopics.size()> writers_;
  std::array<std::mutex, kAllTopics.size()> send_mutex_;  // guards scratch_
  std::array<BorrowScratch, kAllTopics.size()> scratch_;
  std::vector<std::unique_ptr<Inbox>> inboxes_;
  std::thread thread_;
};

}  // namespace

std::unique_ptr<Transport> make_transport(const Options& options, Receiver& receiver) {
  return std::make_unique<DdsTransport>(options, receiver);
}

}  // namespace rigid::transport::dds
