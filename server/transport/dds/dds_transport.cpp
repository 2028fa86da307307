#include "transport/dds/dds_transport.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <mutex>
#include <string_view>
#include <thread>
#include <type_traits>
#include <unordered_map>
#include <vector>

#include "transport/dds/dds_convert.hpp"
#include "transport/dds/dds_entity.hpp"
#include "transport/dds/dds_qos.hpp"
#include "transport/dds/dds_security.hpp"
#include "transport/dds/participant_add_on.hpp"
#include "transport/message_topic.hpp"
#include "transport/traffic_counter.hpp"
#include "util/thread_name.hpp"

namespace rigid::transport::dds {

static_assert(kDefaultStateHistory == kStateReaderDepth);

namespace {

void deliver(Receiver& receiver, const StateFrame& message, const Origin& /*origin*/) {
  receiver.on_state(message);
}
void deliver(Receiver& receiver, const WrenchCommand& message, const Origin& origin) {
  receiver.on_wrench(message, origin);
}
void deliver(Receiver& receiver, const ControlCommand& message, const Origin& origin) {
  receiver.on_control(message, origin);
}
void deliver(Receiver& receiver, const EditCommand& message, const Origin& origin) {
  receiver.on_edit(message, origin);
}

// With DDS Security, who wrote a command: the identity and body named by the writer's partition
// (push/IDENTITY/BODY, or control/IDENTITY for controls and edits), which access control lets only
// that identity use.
// Looked up once per remote writer (dds_get_matched_publication_data allocates) and kept; the
// cache is bounded (cleared when full: a writer is then looked up again).
class WriterPartitions {
 public:
  struct Entry {
    std::string identity;
    std::string body;
    bool ok = false;
  };
  const Entry& lookup(dds_entity_t reader, dds_instance_handle_t writer) {
    if (auto it = cache_.find(writer); it != cache_.end()) return it->second;
    if (cache_.size() >= kMaxWriters) cache_.clear();
    Entry entry;
    if (dds_builtintopic_endpoint_t* ep = dds_get_matched_publication_data(reader, writer)) {
      uint32_t n = 0;
      char** names = nullptr;
      if (ep->qos != nullptr && dds_qget_partition(ep->qos, &n, &names) && n == 1) {
        entry = parse(names[0]);
      }
      for (uint32_t i = 0; i < n; ++i)
        dds_free(names[i]);
      dds_free(names);
      dds_builtintopic_free_endpoint(ep);
    }
    return cache_.emplace(writer, std::move(entry)).first->second;
  }

 private:
  static constexpr std::size_t kMaxWriters = 4096;
  static Entry parse(std::string_view partition) {
    Entry e;
    // A writer's partition with wildcards would be matched as a pattern: never an identity.
    if (partition.find_first_of("*?[]\\") != std::string_view::npos) return e;
    const auto first = partition.find('/');
    if (first == std::string_view::npos) return e;
    const std::string_view kind = partition.substr(0, first);
    const std::string_view rest = partition.substr(first + 1);
    if (kind == kControlPartition) {
      if (rest.empty() || rest.find('/') != std::string_view::npos) return e;
      e.identity = rest;
      e.ok = true;
    } else if (kind == kPushPartition) {
      const auto second = rest.find('/');
      if (second == std::string_view::npos || second == 0 || second + 1 == rest.size()) return e;
      e.identity = rest.substr(0, second);
      e.body = rest.substr(second + 1);
      e.ok = true;
    }
    return e;
  }
  std::unordered_map<dds_instance_handle_t, Entry> cache_;
};
void deliver(Receiver& receiver, const ControlReply& message, const Origin& /*origin*/) {
  receiver.on_control_reply(message);
}
void deliver(Receiver& receiver, const StatsReport& message, const Origin& /*origin*/) {
  receiver.on_stats(message);
}
void deliver(Receiver& receiver, const SceneDescription& message, const Origin& /*origin*/) {
  receiver.on_scene(message);
}
void deliver(Receiver& receiver, const AcceptedCommand& message, const Origin& /*origin*/) {
  receiver.on_accepted(message);
}
void deliver(Receiver& receiver, const ContactEvents& message, const Origin& /*origin*/) {
  receiver.on_contacts(message);
}

// A reader and what it takes samples into: the idlc sample (its sequences grow to the largest
// message seen, then are reused) and the plain message handed to the Receiver.
class Inbox {
 public:
  virtual ~Inbox() = default;
  // Takes the available samples, at most kMaxPerDrain, and hands each to the receiver.
  virtual void drain(Receiver& receiver, TrafficCounter& counter, bool secure) = 0;
  // A reader still holding samples triggers the waitset again at once, and the readers take turns:
  // a reader flooded about as fast as it is drained (10^5 wrenches a second) cannot starve the
  // others (a control request could wait hundreds of milliseconds behind such a flood:
  // bench/notes/flood.md). At most
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

  void drain(Receiver& receiver, TrafficCounter& counter, bool secure) override {
    // A non-null buffer makes dds_take copy into our sample instead of lending one.
    void* buffer[1] = {&sample_};
    dds_sample_info_t info;
    for (int n = 0; n < kMaxPerDrain && dds_take(reader_.get(), buffer, &info, 1, 1) > 0; ++n) {
      if (!info.valid_data) continue;  // a dispose or unregister notice, no data
      const DecodeStatus status = copy_from(sample_, message_);
      if (status == DecodeStatus::kOk) {
        counter.received();
        Origin origin;
        origin.session = info.publication_handle;
        if (secure && is_command) {
          const WriterPartitions::Entry& who =
              partitions_.lookup(reader_.get(), info.publication_handle);
          if (who.ok) {
            origin.identity = who.identity;
            origin.permitted_body = who.body;
            origin.authenticated = true;
          }
        }
        deliver(receiver, message_, origin);
      } else {
        counter.decode_failed();
        receiver.on_decode_error({Bus::kDds, DdsTypeOf<Plain>::topic, status, 0});
      }
    }
  }

 private:
  static constexpr bool is_command = transport::is_command(DdsTypeOf<Plain>::topic);
  typename DdsTypeOf<Plain>::type sample_{};
  Plain message_;
  WriterPartitions partitions_;
};

class DdsTransport final : public Transport {
 public:
  DdsTransport(const Options& options, Receiver& receiver, std::shared_ptr<ParticipantAddOn> add_on)
      : role_(options.role), receiver_(receiver), add_on_(std::move(add_on)) {
    if (!is_valid_prefix(options.prefix)) {
      throw TransportError("DDS: invalid prefix '" + options.prefix +
                           "' (letters, digits and '_' only)");
    }
    if (options.state_history < 1 || options.state_history > kMaxStateHistory) {
      throw TransportError("DDS: state_history " + std::to_string(options.state_history) +
                           " out of range (1 .. " + std::to_string(kMaxStateHistory) + ")");
    }
    Qos participant_qos;
    if (!options.security.empty()) {
      identity_ = load_identity(options.security);
      participant_qos = participant_security_qos(identity_);
    }
    if (add_on_) {
      if (!participant_qos) participant_qos = Qos(dds_create_qos());
      const std::string user_data = add_on_->participant_user_data();
      dds_qset_userdata(participant_qos.get(), user_data.data(), user_data.size());
    }
    participant_ = Entity(
        dds_create_participant(options.domain, participant_qos.get(), nullptr),
        "participant on domain " + std::to_string(options.domain) +
            (secure()
                 ? " with DDS Security from " + identity_.directory +
                       " (is its certificate expired or revoked, or are its files from another "
                       "keystore? rigid-keys list KEYSTORE tells)"
                 : " (is CYCLONEDDS_URI a readable config? scripts/net-setup prints the "
                   "loopback one)"));
    waitset_ = Entity(dds_create_waitset(participant_.get()), "waitset");
    stop_ = Entity(dds_create_guardcondition(participant_.get()), "guard condition");
    check(dds_waitset_attach(waitset_.get(), stop_.get(), kStopToken), "attach guard condition");

    const TopicNames names = dds_topic_names(options.prefix);
    create<StateFrame>(names, options);
    create<WrenchCommand>(names, options);
    create<ControlCommand>(names, options);
    create<ControlReply>(names, options);
    create<StatsReport>(names, options);
    create<SceneDescription>(names, options);
    create<AcceptedCommand>(names, options);
    create<ContactEvents>(names, options);
    create<EditCommand>(names, options);
    if (add_on_) {
      const std::vector<dds_entity_t> conditions =
          add_on_->open(participant_.get(), receiver_, counter_);
      for (std::size_t i = 0; i < conditions.size(); ++i) {
        check(dds_waitset_attach(waitset_.get(), conditions[i],
                                 kAddOnToken + static_cast<dds_attach_t>(i)),
              "attach a condition of the participant's other face");
      }
      triggered_.resize(triggered_.size() + conditions.size());
    }

    thread_ = std::thread([this] { receive_loop(); });
    util::name_thread(thread_, "rigid-dds-in");
  }

  ~DdsTransport() override {
    dds_set_guardcondition(stop_.get(), true);
    if (thread_.joinable()) thread_.join();
    if (add_on_) add_on_->close();
  }

  DdsTransport(const DdsTransport&) = delete;
  DdsTransport& operator=(const DdsTransport&) = delete;

  Bus bus() const override { return Bus::kDds; }
  Role role() const override { return role_; }

  PublishResult publish(const StateFrame& m) override {
    const PublishResult result = write(m);
    if (add_on_ && result == PublishResult::kOk) add_on_->on_state(m);
    return result;
  }
  PublishResult publish(const StatsReport& m) override { return write(m); }
  PublishResult publish(const SceneDescription& m) override {
    const PublishResult result = write(m);
    if (add_on_ && result == PublishResult::kOk) add_on_->on_scene(m);
    return result;
  }
  PublishResult publish(const ControlReply& m) override {
    if (add_on_ && add_on_->on_control_reply(m)) return PublishResult::kOk;
    return write(m);
  }
  PublishResult publish(const WrenchCommand& m) override {
    if (!secure() || role_ != Role::kClient) return write(m);
    // With security a wrench goes out through the writer of its body's partition.
    if (m.body_name.empty() || m.body_name.size() > kMaxNameLength) return PublishResult::kInvalid;
    constexpr std::size_t i = index_of(Topic::kWrench);
    const std::lock_guard lock(send_mutex_[i]);
    const dds_entity_t writer =
        command_writer(Topic::kWrench, push_partition(identity_.name, m.body_name));
    if (writer <= 0) return PublishResult::kNotPermitted;
    return write_with(writer, m, scratch_[i]);
  }
  PublishResult publish(const ControlCommand& m) override { return write_controlled(m); }
  PublishResult publish(const EditCommand& m) override { return write_controlled(m); }
  PublishResult publish(const AcceptedCommand& m) override {
    const PublishResult result = write(m);
    if (add_on_ && result == PublishResult::kOk) add_on_->on_accepted(m);
    return result;
  }
  PublishResult publish(const ContactEvents& m) override { return write(m); }

  TransportCounts counts() const override { return counter_.snapshot(); }

 private:
  // The waitset token of the stop condition; readers use their index in inboxes_, the add-on's
  // conditions kAddOnToken + their index in its list.
  static constexpr dds_attach_t kStopToken = -1;
  static constexpr dds_attach_t kAddOnToken = 1 << 20;

  static void check(dds_return_t result, const std::string& what) {
    if (result < 0) throw TransportError("DDS: cannot " + what + ": " + dds_strretcode(result));
  }

  template <class Plain>
  void create(const TopicNames& names, const Options& options) {
    constexpr Topic topic = DdsTypeOf<Plain>::topic;
    const std::string& name = names[index_of(topic)];
    Qos qos = topic_qos(topic, options.reliable_state);
    Entity& entity = topics_[index_of(topic)];
    const dds_entity_t created = dds_create_topic(participant_.get(), DdsTypeOf<Plain>::descriptor,
                                                  name.c_str(), qos.get(), nullptr);
    // rigid/contacts came after the first keystores: a server identity made before it may not
    // publish it, and goes without (publishing contact events is then kNotPermitted).
    const bool optional = role_ == Role::kClient || topic == Topic::kContacts;
    if (created == DDS_RETCODE_NOT_ALLOWED_BY_SECURITY && optional) {
      // This identity's permissions leave the topic out (a reader cannot write wrenches, an
      // identity that may not control gets no control replies): it simply does without.
      return;
    }
    entity =
        Entity(created, "topic " + name + (secure() ? " (not permitted to this identity?)" : ""));
    if (secure() && is_command(topic)) {
      if (role_ == Role::kClient) return;  // a writer per partition, made when first needed
      // The server reads every identity's partition of the topic.
      const std::string any =
          std::string(topic == Topic::kWrench ? kPushPartition : kControlPartition) + "/*";
      const char* partitions[] = {any.c_str()};
      dds_qset_partition(qos.get(), 1, partitions);
    }
    if (publishes(role_, topic)) {
      const dds_entity_t writer =
          dds_create_writer(participant_.get(), entity.get(), qos.get(), nullptr);
      if (writer == DDS_RETCODE_NOT_ALLOWED_BY_SECURITY && optional) return;
      writers_[index_of(topic)] = Entity(writer, "writer for " + name);
    } else {
      if (topic == Topic::kState)
        qos = reader_qos(topic, options.reliable_state, options.state_history);
      inboxes_.push_back(
          std::make_unique<TypedInbox<Plain>>(participant_.get(), entity.get(), qos.get(), name));
      check(dds_waitset_attach(waitset_.get(), inboxes_.back()->condition(),
                               static_cast<dds_attach_t>(inboxes_.size() - 1)),
            "attach read condition for " + name);
    }
  }

  // A control or an edit: with security, through the writer of the identity's control partition.
  template <class Plain>
  PublishResult write_controlled(const Plain& m) {
    if (!secure() || role_ != Role::kClient) return write(m);
    constexpr Topic topic = DdsTypeOf<Plain>::topic;
    constexpr std::size_t i = index_of(topic);
    const std::lock_guard lock(send_mutex_[i]);
    const dds_entity_t writer = command_writer(topic, control_partition(identity_.name));
    if (writer <= 0) return PublishResult::kNotPermitted;
    return write_with(writer, m, scratch_[i]);
  }

  template <class Plain>
  PublishResult write(const Plain& message) {
    constexpr Topic topic = DdsTypeOf<Plain>::topic;
    constexpr std::size_t i = index_of(topic);
    if (writers_[i].get() <= 0) {
      return publishes(role_, topic) ? PublishResult::kNotPermitted : PublishResult::kWrongRole;
    }
    const std::lock_guard lock(send_mutex_[i]);
    return write_with(writers_[i].get(), message, scratch_[i]);
  }

  template <class Plain>
  PublishResult write_with(dds_entity_t writer, const Plain& message, BorrowScratch& scratch) {
    typename DdsTypeOf<Plain>::type sample{};
    if (!borrow(message, scratch, sample)) return PublishResult::kInvalid;
    const dds_return_t result = dds_write(writer, &sample);
    // SceneInfo goes out once, at start (the topic's durability keeps it for late joiners): the
    // scratch its names took (129 B a body) need not stay.
    if constexpr (std::is_same_v<Plain, SceneDescription>) scratch = BorrowScratch{};
    return counter_.count(result == DDS_RETCODE_OK ? PublishResult::kOk : PublishResult::kFailed);
  }

  bool secure() const { return !identity_.name.empty(); }

  // With security, a client's writer of one command topic for one partition (push/NAME/BODY,
  // control/NAME), made the first time it is needed: access control refuses one the identity's
  // permissions do not allow (0 is returned, and remembered). A new writer is given a moment to
  // match the server's reader, or its first command would go to no one. The caller holds the
  // topic's lock.
  dds_entity_t command_writer(Topic topic, const std::string& partition) {
    std::map<std::string, Entity>& writers = command_writers_[index_of(topic)];
    if (auto it = writers.find(partition); it != writers.end()) return it->second.get();
    if (writers.size() >= kMaxCommandWriters) return 0;
    if (topics_[index_of(topic)].get() <= 0) return 0;  // the identity has no such topic
    const Qos qos = topic_qos(topic, false);
    const char* partitions[] = {partition.c_str()};
    dds_qset_partition(qos.get(), 1, partitions);
    const dds_entity_t writer =
        dds_create_writer(participant_.get(), topics_[index_of(topic)].get(), qos.get(), nullptr);
    if (writer < 0) {
      writers.emplace(partition, Entity());
      return 0;
    }
    Entity& entity = writers.emplace(partition, Entity(writer, "writer")).first->second;
    const std::int64_t give_up = dds_time() + DDS_SECS(2);
    dds_publication_matched_status_t matched{};
    while (dds_get_publication_matched_status(writer, &matched) == DDS_RETCODE_OK &&
           matched.current_count == 0 && dds_time() < give_up) {
      dds_sleepfor(DDS_MSECS(5));
    }
    return entity.get();
  }

  void receive_loop() {
    std::vector<dds_attach_t>& triggered = triggered_;
    for (;;) {
      const dds_return_t n =
          dds_waitset_wait(waitset_.get(), triggered.data(), triggered.size(), DDS_INFINITY);
      if (n < 0) return;  // the waitset is gone: the transport is being destroyed
      const auto count = std::min(static_cast<std::size_t>(n), triggered.size());
      for (std::size_t k = 0; k < count; ++k) {
        const dds_attach_t token = triggered[k];
        if (token == kStopToken) return;
        if (token >= kAddOnToken) {
          add_on_->on_triggered(static_cast<std::size_t>(token - kAddOnToken));
          continue;
        }
        inboxes_[static_cast<std::size_t>(token)]->drain(receiver_, counter_, secure());
      }
    }
  }

  static constexpr std::size_t kMaxCommandWriters = 1024;

  const Role role_;
  Receiver& receiver_;
  TrafficCounter counter_;
  Identity identity_;  // name empty: no security
  // Declaration order is destruction order reversed: the participant goes last.
  Entity participant_;
  // After the participant: destroyed before it, with its entities.
  std::shared_ptr<ParticipantAddOn> add_on_;
  Entity waitset_;
  Entity stop_;
  std::array<Entity, kAllTopics.size()> topics_;
  std::array<Entity, kAllTopics.size()> writers_;
  std::array<std::mutex, kAllTopics.size()> send_mutex_;  // guards scratch_
  std::array<BorrowScratch, kAllTopics.size()> scratch_;
  std::vector<std::unique_ptr<Inbox>> inboxes_;
  // By topic, then partition; each map guarded by its topic's send_mutex_.
  std::array<std::map<std::string, Entity>, kAllTopics.size()> command_writers_;
  // The receive thread's waitset results: one per reader, the stop condition and the add-on's.
  std::vector<dds_attach_t> triggered_ = std::vector<dds_attach_t>(kAllTopics.size() + 1);
  std::thread thread_;
};

}  // namespace

std::unique_ptr<Transport> make_transport(const Options& options, Receiver& receiver) {
  return std::make_unique<DdsTransport>(options, receiver, nullptr);
}

std::unique_ptr<Transport> make_transport(const Options& options, Receiver& receiver,
                                          std::shared_ptr<ParticipantAddOn> add_on) {
  return std::make_unique<DdsTransport>(options, receiver, std::move(add_on));
}

void limit_sample_size(std::size_t bytes) {
  const char* uri = std::getenv("CYCLONEDDS_URI");
  std::string value = uri != nullptr ? uri : "";
  value += std::string(value.empty() ? "" : ",") +
           "<CycloneDDS><Domain id=\"any\"><Internal><MaxSampleSize>" + std::to_string(bytes) +
           "B</MaxSampleSize></Internal></Domain></CycloneDDS>";
  ::setenv("CYCLONEDDS_URI", value.c_str(), 1);
}

std::string ensure_dds_config() {
  namespace fs = std::filesystem;
  if (const char* uri = std::getenv("CYCLONEDDS_URI"); uri != nullptr && uri[0] != '\0') {
    std::string line = std::string("CYCLONEDDS_URI=") + uri;
    if (std::string_view(uri).find("<NetworkInterface") == std::string_view::npos &&
        std::string_view(uri).find("file:") == 0) {
      // Name the interfaces the file pins, so the start line says where DDS goes.
      std::ifstream in(
          std::string(uri).substr(std::string_view(uri).starts_with("file://") ? 7 : 5));
      std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      std::string names;
      for (std::size_t at = text.find("<NetworkInterface"); at != std::string::npos;
           at = text.find("<NetworkInterface", at + 1)) {
        const std::size_t name = text.find("name=\"", at);
        const std::size_t end = name == std::string::npos ? name : text.find('"', name + 6);
        if (end == std::string::npos) break;
        names += (names.empty() ? "" : ",") + text.substr(name + 6, end - name - 6);
      }
      line += names.empty() ? " (interfaces: Cyclone's choice)" : " (interfaces: " + names + ")";
    }
    return line;
  }
  // The installed configuration first (next to the program, whatever the prefix it was installed
  // to; then at the configured prefix), then the source tree's (a build run from its tree).
  std::error_code error;
  const fs::path program = fs::read_symlink("/proc/self/exe", error);
  const std::string beside =
      error ? std::string()
            : (program.parent_path() / RIGID_DATADIR_FROM_BINDIR / "rigid" / "cyclonedds.xml")
                  .lexically_normal()
                  .string();
  for (const std::string& candidate :
       {beside, std::string(RIGID_INSTALLED_DDS_CONFIG), std::string(RIGID_SOURCE_DDS_CONFIG)}) {
    if (!candidate.empty() && fs::is_regular_file(candidate, error)) {
      const std::string uri = "file://" + candidate;
      ::setenv("CYCLONEDDS_URI", uri.c_str(), 1);
      return "CYCLONEDDS_URI=" + uri + " (interfaces: lo; CYCLONEDDS_URI was unset)";
    }
  }
  return "CYCLONEDDS_URI unset and no loopback config found: Cyclone DDS picks an interface";
}

}  // namespace rigid::transport::dds
