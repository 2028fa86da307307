// Ownership of Cyclone DDS entities (participant, topic, writer, reader, waitset, conditions) and
// QoS objects: each is deleted exactly once, when its owner goes.
#pragma once

#include <dds/dds.h>

#include <memory>
#include <string>
#include <string_view>
#include <utility>

#include "transport/transport.hpp"

namespace rigid::transport::dds {

class Entity {
 public:
  Entity() = default;
  // Takes the result of a dds_create_* call; a negative one is an error naming `what`.
  Entity(dds_entity_t result, std::string_view what) : handle_(result) {
    if (result < 0) {
      throw TransportError("DDS: cannot create " + std::string(what) + ": " +
                           dds_strretcode(result));
    }
  }
  ~Entity() { reset(); }
  Entity(Entity&& other) noexcept : handle_(std::exchange(other.handle_, 0)) {}
  Entity& operator=(Entity&& other) noexcept {
    if (this != &other) {
      reset();
      handle_ = std::exchange(other.handle_, 0);
    }
    return *this;
  }
  Entity(const Entity&) = delete;
  Entity& operator=(const Entity&) = delete;

  dds_entity_t get() const { return handle_; }

 private:
  void reset() {
    if (handle_ > 0) dds_delete(handle_);
    handle_ = 0;
  }
  dds_entity_t handle_ = 0;
};

struct QosDeleter {
  void operator()(dds_qos_t* qos) const { dds_delete_qos(qos); }
};
using Qos = std::unique_ptr<dds_qos_t, QosDeleter>;

}  // namespace rigid::transport::dds
