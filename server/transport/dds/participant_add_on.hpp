// Another face of the DDS transport on its one participant (rigidd --ros: ros/ros_face.hpp): the
// transport hands it the participant to make its own topics on, waits for its readers on the
// transport's receive thread (so that every command of the bus reaches the Receiver from one
// thread), and tells it what the transport publishes, so that it can publish the same in its own
// vocabulary.
#pragma once

#include <dds/dds.h>

#include <cstddef>
#include <string>
#include <vector>

#include "rigid/messages.hpp"
#include "transport/traffic_counter.hpp"
#include "transport/transport.hpp"

namespace rigid::transport::dds {

class ParticipantAddOn {
 public:
  virtual ~ParticipantAddOn() = default;

  // The participant's USER_DATA, set before it is created.
  virtual std::string participant_user_data() const = 0;
  // Creates its entities on `participant`. Commands it receives go to `receiver` and are counted
  // in `counter`, like the transport's own. Returns the conditions the transport's receive thread
  // waits on for it (on_triggered's index is a position in this list). Throws TransportError.
  virtual std::vector<dds_entity_t> open(dds_entity_t participant, Receiver& receiver,
                                         TrafficCounter& counter) = 0;
  // The transport's receive thread: condition `index` triggered.
  virtual void on_triggered(std::size_t index) = 0;
  // Deletes its entities; the transport's receive thread has ended. Before the participant goes.
  virtual void close() = 0;

  // What the transport published (from the thread that published it).
  virtual void on_state(const StateFrame& /*state*/) {}
  virtual void on_scene(const SceneDescription& /*scene*/) {}
  virtual void on_accepted(const AcceptedCommand& /*accepted*/) {}
  // A reply about to be published: true if it answers a request of the add-on's, which then sent
  // the answer itself (the transport publishes it not).
  virtual bool on_control_reply(const ControlReply& /*reply*/) { return false; }
};

}  // namespace rigid::transport::dds
