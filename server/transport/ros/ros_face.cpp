#include "transport/ros/ros_face.hpp"

#include <algorithm>
#include <mutex>
#include <unordered_map>
#include <utility>

#include "transport/dds/participant_add_on.hpp"
#include "transport/ros/markers.hpp"
#include "transport/ros/raw_sertype.hpp"
#include "transport/ros/ros_names.hpp"
#include "transport/ros/ros_qos.hpp"
#include "transport/ros/sim_server.hpp"
#include "transport/ros/tf_message.hpp"

namespace rigid::transport::ros {
namespace {

// tf2_ros's DynamicBroadcasterQoS: reliable, volatile, depth 100; StaticBroadcasterQoS:
// transient local, depth 1 (every static transform in one message).
constexpr std::int32_t kTfDepth = 100;
// Commands are kept like rigid's own (dds_qos.cpp): a burst is not collapsed.
constexpr std::int32_t kWrenchDepth = 256;
// At most this many publishers per body are remembered for clearing their wrenches.
constexpr std::size_t kMaxPushersPerBody = 16;
// An upper bound of one Marker's bytes besides its frame name (markers.cpp's layout: 258 B).
constexpr std::size_t kMarkerBytes = 320;

std::string wrench_topic_name(const Options& o, const std::string& body) {
  return o.ns + "/rigid/" + body + "/wrench";
}

bool has_wrench_topic(const Options& o, const std::string& body) {
  return is_valid_relative_name(body) && wrench_topic_name(o, body).size() <= kMaxTopicNameLength;
}

std::string hex12(const std::uint8_t* b) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string s;
  for (int i = 0; i < 12; ++i) {
    s += kDigits[b[i] >> 4];
    s += kDigits[b[i] & 15];
  }
  return s;
}

class RosFace final : public dds::ParticipantAddOn {
 public:
  explicit RosFace(Options options) : opt_(std::move(options)) {}

  // rmw_cyclonedds's participant USER_DATA: the SROS2 enclave, "/" when not set.
  std::string participant_user_data() const override { return "enclave=/;"; }

  std::vector<dds_entity_t> open(dds_entity_t participant, Receiver& receiver,
                                 TrafficCounter& counter) override {
    receiver_ = &receiver;
    counter_ = &counter;
    const auto writer = [&](RawTopic& topic, const std::string& name, const std::string& type,
                            const dds::Qos& qos, dds::Entity& out) {
      topic = RawTopic(participant, name, type, qos.get());
      out = dds::Entity(dds_create_writer(participant, topic.get(), qos.get(), nullptr),
                        "writer for " + name);
    };
    writer(tf_topic_, dds_topic(opt_.ns + "/tf"), dds_message_type("tf2_msgs", "TFMessage"),
           ros_qos(Durability::kVolatile, kTfDepth), tf_writer_);
    writer(static_topic_, dds_topic(opt_.ns + "/tf_static"),
           dds_message_type("tf2_msgs", "TFMessage"), ros_qos(Durability::kTransientLocal, 1),
           static_writer_);
    writer(clock_topic_, dds_topic("/clock"), dds_message_type("rosgraph_msgs", "Clock"),
           ros_qos(Durability::kVolatile, 1), clock_writer_);
    writer(markers_topic_, dds_topic(opt_.ns + "/rigid/markers"),
           dds_message_type("visualization_msgs", "MarkerArray"),
           ros_qos(Durability::kTransientLocal, 1), markers_writer_);

    // The wrench readers are not waited on one by one: a waitset's wait looks at every condition
    // attached to it on every wake, and a scene's thousand readers made each command cost the
    // receive thread more than its own work (bench/notes/ros.md). Each reader's listener notes it
    // as ready instead, and one guard condition wakes the receive thread.
    wrench_ready_ = dds::Entity(dds_create_guardcondition(participant), "guard condition");
    std::vector<dds_entity_t> conditions{wrench_ready_.get()};
    const dds::Qos wrench_qos = ros_qos(Durability::kVolatile, kWrenchDepth);
    wrenches_.reserve(opt_.body_names.size());  // the listeners hold their inbox's address
    queued_.assign(opt_.body_names.size(), 0);  // a listener may run as soon as its reader exists
    for (std::size_t b = 0; b < opt_.body_names.size(); ++b) {
      const std::string& body = opt_.body_names[b];
      if (!has_wrench_topic(opt_, body)) continue;
      WrenchInbox& in = wrenches_.emplace_back();
      in.face = this;
      in.index = wrenches_.size() - 1;
      in.body = static_cast<std::int32_t>(b);
      in.topic = RawTopic(participant, dds_topic(wrench_topic_name(opt_, body)),
                          dds_message_type("geometry_msgs", "WrenchStamped"), wrench_qos.get());
      dds_listener_t* listener = dds_create_listener(&in);
      dds_lset_data_available(listener, &RosFace::on_data_available);
      in.reader =
          dds::Entity(dds_create_reader(participant, in.topic.get(), wrench_qos.get(), listener),
                      "reader for " + in.topic.name());
      dds_delete_listener(listener);
    }

    SimServer::Setup setup;
    setup.node_fq_name = opt_.ns + "/" + opt_.node_name;
    setup.world_frame = opt_.world_frame;
    setup.body_names = opt_.body_names;
    setup.mode = opt_.mode;
    setup.secure = opt_.secure;
    sim_ = std::make_unique<SimServer>(participant, std::move(setup), receiver, counter);
    for (const dds_entity_t c : sim_->conditions())
      conditions.push_back(c);

    tf_ids_.resize(opt_.body_names.size());
    for (std::size_t i = 0; i < tf_ids_.size(); ++i)
      tf_ids_[i] = static_cast<std::int32_t>(i);
    tf_.build(opt_.world_frame, opt_.body_names);

    publish_discovery(participant);
    return conditions;
  }

  void on_triggered(std::size_t index) override {
    if (index > 0) {
      if (sim_) sim_->on_triggered(index - 1);
      return;
    }
    bool triggered = false;
    (void)dds_take_guardcondition(wrench_ready_.get(), &triggered);
    {
      const std::lock_guard lock(ready_mutex_);
      draining_.swap(ready_);
      for (const std::size_t i : draining_)
        queued_[i] = 0;
    }
    for (const std::size_t i : draining_)
      if (drain(wrenches_[i])) mark_ready(i);  // more left: another turn, after the others
    draining_.clear();
  }

  void close() override {
    if (sim_) sim_->close();
    wrenches_.clear();
    wrench_ready_ = dds::Entity();
    discovery_writer_ = dds::Entity();
    markers_writer_ = dds::Entity();
    clock_writer_ = dds::Entity();
    static_writer_ = dds::Entity();
    tf_writer_ = dds::Entity();
    for (RawTopic* t :
         {&tf_topic_, &static_topic_, &clock_topic_, &markers_topic_, &discovery_topic_})
      *t = RawTopic();
  }

  void on_state(const StateFrame& state) override {
    if (!std::equal(state.ids.begin(), state.ids.end(), tf_ids_.begin(), tf_ids_.end())) {
      // Bodies other than the scene's, in another order: a new template (allocates; never
      // happens with today's loop, whose states list every body in id order).
      std::vector<std::string> children;
      for (const std::int32_t id : state.ids)
        children.push_back(id >= 0 && static_cast<std::size_t>(id) < opt_.body_names.size()
                               ? opt_.body_names[static_cast<std::size_t>(id)]
                               : "body_" + std::to_string(id));
      tf_.build(opt_.world_frame, children);
      tf_ids_ = state.ids;
    }
    // /tf and /clock go only to matched readers: with none there is nothing to build.
    if (has_readers(tf_writer_.get())) {
      tf_.fill(state);
      counter_->count(write(tf_topic_, tf_writer_.get(), tf_.bytes()));
    }
    if (has_readers(clock_writer_.get())) {
      encode_clock(ros_time(state.sim_time), clock_bytes_);
      counter_->count(write(clock_topic_, clock_writer_.get(), clock_bytes_));
    }
    if (sim_) sim_->on_state(state);
  }

  void on_scene(const SceneDescription& scene) override {
    std::vector<std::uint8_t> bytes;
    encode_markers(scene, opt_.static_frames, bytes);
    counter_->count(write(markers_topic_, markers_writer_.get(), bytes));
    if (!opt_.static_frames.empty()) {
      TfMessage statics;
      std::vector<std::string> names;
      for (const StaticFrame& f : opt_.static_frames)
        names.push_back(f.name);
      statics.build(opt_.world_frame, names);
      for (std::size_t i = 0; i < opt_.static_frames.size(); ++i)
        statics.set_pose(i, opt_.static_frames[i].p_WS.data(),
                         opt_.static_frames[i].q_WS_wxyz.data());
      counter_->count(write(static_topic_, static_writer_.get(), statics.bytes()));
    }
  }

  void on_accepted(const AcceptedCommand& accepted) override {
    if (sim_) sim_->on_accepted(accepted);
  }

  bool on_control_reply(const ControlReply& reply) override {
    return sim_ && sim_->on_control_reply(reply);
  }

 private:
  struct WrenchInbox {
    RosFace* face = nullptr;
    std::size_t index = 0;  // in wrenches_
    std::int32_t body = 0;
    RawTopic topic;
    dds::Entity reader;
  };

  // A wrench reader's listener, on Cyclone's delivery thread: notes the reader as ready and wakes
  // the receive thread. Quick, and takes no lock the receive thread holds while it calls into
  // Cyclone.
  static void on_data_available(dds_entity_t /*reader*/, void* arg) {
    const auto* in = static_cast<const WrenchInbox*>(arg);
    in->face->mark_ready(in->index);
  }
  void mark_ready(std::size_t index) {
    {
      const std::lock_guard lock(ready_mutex_);
      if (queued_[index] != 0) return;
      queued_[index] = 1;
      ready_.push_back(index);
    }
    dds_set_guardcondition(wrench_ready_.get(), true);
  }

  static PublishResult write(const RawTopic& topic, dds_entity_t writer,
                             std::span<const std::uint8_t> bytes) {
    return topic.write(writer, bytes) >= 0 ? PublishResult::kOk : PublishResult::kFailed;
  }

  static bool has_readers(dds_entity_t writer) {
    dds_publication_matched_status_t s{};
    return dds_get_publication_matched_status(writer, &s) == DDS_RETCODE_OK && s.current_count > 0;
  }

  // ros_discovery_info: this participant's one node and the GIDs of its ROS endpoints, which is
  // how `ros2 node list` and `ros2 node info` know rigidd (rmw_dds_common's graph cache).
  void publish_discovery(dds_entity_t participant) {
    const dds::Qos qos = ros_qos(Durability::kTransientLocal, 1);
    discovery_topic_ =
        RawTopic(participant, "ros_discovery_info",
                 dds_message_type("rmw_dds_common", "ParticipantEntitiesInfo"), qos.get());
    discovery_writer_ =
        dds::Entity(dds_create_writer(participant, discovery_topic_.get(), qos.get(), nullptr),
                    "writer for ros_discovery_info");
    NodeEntities node;
    node.node_namespace = opt_.ns.empty() ? "/" : opt_.ns;
    node.node_name = opt_.node_name;
    for (const dds::Entity* w : {&tf_writer_, &static_writer_, &clock_writer_, &markers_writer_})
      node.writers.push_back(guid_of(w->get()));
    for (const dds_entity_t w : sim_->writers())
      node.writers.push_back(guid_of(w));
    for (const WrenchInbox& in : wrenches_)
      node.readers.push_back(guid_of(in.reader.get()));
    for (const dds_entity_t r : sim_->readers())
      node.readers.push_back(guid_of(r));
    std::vector<std::uint8_t> bytes;
    encode_participant_entities(guid_of(participant), node, opt_.distro, bytes);
    counter_->count(write(discovery_topic_, discovery_writer_.get(), bytes));
  }

  // Takes as many samples as rigid's own inboxes take per turn (dds_transport.cpp:
  // Inbox::kMaxPerDrain); true if it stopped there with more left.
  bool drain(WrenchInbox& in) {
    for (int n = 0; n < 256; ++n) {
      const int taken = take_raw(
          in.reader.get(), [&](std::span<const std::uint8_t> bytes, const dds_sample_info_t& info) {
            on_sample(in, bytes, info);
          });
      if (taken <= 0) return false;
    }
    return true;
  }

  void on_sample(const WrenchInbox& in, std::span<const std::uint8_t> bytes,
                 const dds_sample_info_t& info) {
    if (!info.valid_data) {
      // No writer left on this body's topic (deleted, or its process gone): what they pushed
      // stops now rather than at its ttl.
      if (info.instance_state == DDS_NOT_ALIVE_NO_WRITERS_INSTANCE_STATE) clear_pushers(in.body);
      return;
    }
    const DecodeStatus status = decode_wrench_stamped(bytes, message_);
    if (status != DecodeStatus::kOk) {
      counter_->decode_failed();
      receiver_->on_decode_error({Bus::kDds, Topic::kWrench, status, bytes.size()});
      return;
    }
    counter_->received();
    const std::string& body = opt_.body_names[static_cast<std::size_t>(in.body)];
    WrenchCommand w;
    w.source = static_cast<std::int64_t>(info.publication_handle);
    w.seq = ++seq_;
    w.key = 0;
    w.body_id = in.body;
    w.force = message_.force;
    w.torque = message_.torque;
    // frame_id names the frame the wrench is expressed in: the world's or the body's. Anything
    // else is refused as an invalid frame (counted like rigid's own).
    const Frame frame = message_.frame_id == opt_.world_frame ? Frame::kWorld
                        : message_.frame_id == body           ? Frame::kBody
                                                              : static_cast<Frame>(-1);
    w.force_frame = frame;
    w.torque_frame = frame;
    w.ttl = opt_.wrench_ttl;
    w.stamp_ns = info.source_timestamp;
    remember_pusher(in.body, info.publication_handle);
    receiver_->on_wrench(w, origin_of(in, info.publication_handle));
  }

  Origin origin_of(const WrenchInbox& in, dds_instance_handle_t writer) {
    Origin origin;
    origin.session = writer;
    if (!opt_.secure) return origin;
    // With DDS Security only identities permitted to push this body can write its topic: the
    // sender is named by its participant, and the body by the topic.
    auto it = identities_.find(writer);
    if (it == identities_.end()) {
      if (identities_.size() >= 4096) identities_.clear();
      std::string id;
      if (dds_builtintopic_endpoint_t* ep =
              dds_get_matched_publication_data(in.reader.get(), writer)) {
        id = "ros:" + hex12(ep->participant_key.v);
        dds_builtintopic_free_endpoint(ep);
      }
      it = identities_.emplace(writer, id).first;
    }
    if (it->second.empty()) return origin;
    origin.identity = it->second;
    origin.permitted_body = opt_.body_names[static_cast<std::size_t>(in.body)];
    origin.authenticated = true;
    return origin;
  }

  void remember_pusher(std::int32_t body, dds_instance_handle_t writer) {
    std::vector<dds_instance_handle_t>& list = pushers_[body];
    if (std::find(list.begin(), list.end(), writer) != list.end()) return;
    if (list.size() >= kMaxPushersPerBody) list.erase(list.begin());
    list.push_back(writer);
  }

  // Each remembered publisher's wrench on `body` replaced by nothing (zero, for the next tick).
  void clear_pushers(std::int32_t body) {
    const auto it = pushers_.find(body);
    if (it == pushers_.end()) return;
    const WrenchInbox* in = nullptr;
    for (const WrenchInbox& w : wrenches_)
      if (w.body == body) in = &w;
    for (const dds_instance_handle_t writer : it->second) {
      WrenchCommand w;
      w.source = static_cast<std::int64_t>(writer);
      w.seq = ++seq_;
      w.body_id = body;
      w.ttl = 0.0;
      Origin plain;
      plain.session = writer;
      receiver_->on_wrench(w, in != nullptr ? origin_of(*in, writer) : plain);
    }
    pushers_.erase(it);
  }

  Options opt_;
  Receiver* receiver_ = nullptr;
  TrafficCounter* counter_ = nullptr;

  RawTopic tf_topic_, static_topic_, clock_topic_, markers_topic_, discovery_topic_;
  dds::Entity tf_writer_, static_writer_, clock_writer_, markers_writer_, discovery_writer_;
  // Wrench readers with samples, noted by their listeners (Cyclone's threads), taken by the
  // receive thread. Before the readers: destroyed after them.
  std::mutex ready_mutex_;
  std::vector<std::size_t> ready_;
  std::vector<std::uint8_t> queued_;   // by reader: in ready_
  std::vector<std::size_t> draining_;  // the receive thread's
  dds::Entity wrench_ready_;           // before the readers: deleted after them
  std::vector<WrenchInbox> wrenches_;
  std::unique_ptr<SimServer> sim_;

  // The transport's publisher thread (states).
  TfMessage tf_;
  std::vector<std::int32_t> tf_ids_;
  std::vector<std::uint8_t> clock_bytes_;

  // The transport's receive thread.
  WrenchStamped message_;
  std::int64_t seq_ = 0;
  std::unordered_map<dds_instance_handle_t, std::string> identities_;
  std::unordered_map<std::int32_t, std::vector<dds_instance_handle_t>> pushers_;
};

}  // namespace

Plan plan(const Options& options) {
  Plan p;
  std::size_t tf_bytes = 8;
  std::size_t marker_bytes = 8;
  for (const std::string& body : options.body_names) {
    if (has_wrench_topic(options, body)) {
      ++p.wrench_topics;
    } else {
      p.notes.push_back("body '" + body + "' has no ROS wrench topic: " +
                        (is_valid_relative_name(body)
                             ? std::string("rigid/") + body + "/wrench is longer than ROS allows"
                             : std::string("ROS names allow letters, digits, '_' and '/', and no "
                                           "token may start with a digit")));
    }
    if (!body.empty() && body.front() == '/') {
      p.notes.push_back("body '" + body + "': tf2 refuses frame names that start with '/'");
    }
    if (body == options.world_frame) {
      p.notes.push_back("body '" + body + "' has the world frame's name: tf2 sees a loop");
    }
    tf_bytes += 112 + options.world_frame.size() + body.size();
    marker_bytes += 3 * (kMarkerBytes + body.size());
  }
  for (const StaticFrame& s : options.static_frames) {
    tf_bytes += 112 + options.world_frame.size() + s.name.size();
    marker_bytes += 3 * (kMarkerBytes + s.name.size());
  }
  p.largest_sample = std::max(tf_bytes, marker_bytes);
  return p;
}

std::shared_ptr<dds::ParticipantAddOn> make_face(const Options& options) {
  return std::make_shared<RosFace>(options);
}

}  // namespace rigid::transport::ros
