// A Cyclone DDS topic type whose samples are bytes rigid serializes and parses itself: keyless,
// plain CDR (XCDR1), under any type name. This is how ROS 2's own Cyclone middleware puts its
// messages on the wire (a custom "sertype", no XTypes type information), so rigid can speak ROS
// 2's types ("tf2_msgs::msg::dds_::TFMessage_", ...) without generated code, and sees every
// received sample's bytes: a malformed one is counted by rigid instead of being dropped silently
// inside Cyclone.
//
// A sample is the serialized message with its 4-byte encapsulation header (ros/cdr.hpp).
#pragma once

#include <dds/dds.h>

#include <cstdint>
#include <span>
#include <string>

#include "transport/dds/dds_entity.hpp"

struct ddsi_sertype;

namespace rigid::transport::ros {

class RawTopic {
 public:
  RawTopic() = default;
  // Creates topic `name` of type `type_name` on `participant` with `qos` (null: defaults). Throws
  // TransportError naming the topic when Cyclone refuses it (with DDS Security: a topic the
  // identity's permissions leave out).
  RawTopic(dds_entity_t participant, const std::string& name, const std::string& type_name,
           const dds_qos_t* qos);
  dds_entity_t get() const { return topic_.get(); }
  const std::string& name() const { return name_; }

  // Writes `bytes` (encapsulation header included) with `writer`, a writer of this topic.
  dds_return_t write(dds_entity_t writer, std::span<const std::uint8_t> bytes) const;

 private:
  std::string name_;
  dds::Entity topic_;
  const ddsi_sertype* sertype_ = nullptr;  // Cyclone's, valid while the topic exists
};

// Takes at most one sample from `reader` (a reader of a RawTopic). Returns 1 and calls
// fn(bytes, info) while the sample is held (bytes are valid during the call only), 0 when there
// is none, < 0 on error. A sample without data (a writer gone) calls fn with empty bytes and
// info.valid_data false.
template <class F>
int take_raw(dds_entity_t reader, F&& fn);

// The implementation of take_raw: the bytes of a sample Cyclone lent.
std::span<const std::uint8_t> raw_bytes(const struct ddsi_serdata* sample);
void release_raw(struct ddsi_serdata* sample);

template <class F>
int take_raw(dds_entity_t reader, F&& fn) {
  struct ddsi_serdata* sample = nullptr;
  dds_sample_info_t info;
  const dds_return_t n = dds_takecdr(reader, &sample, 1, &info, DDS_ANY_STATE);
  if (n <= 0) return n;
  fn(info.valid_data ? raw_bytes(sample) : std::span<const std::uint8_t>(), info);
  release_raw(sample);
  return 1;
}

}  // namespace rigid::transport::ros
