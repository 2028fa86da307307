#include "transport/dds/dds_qos.hpp"

namespace rigid::transport::dds {
namespace {

// Commands are kept, not just the latest, so a burst from one controller is not collapsed; past
// this many unread ones the oldest go, so a flood never blocks the controller's writer.
constexpr int kCommandDepth = 256;
constexpr int kReplyDepth = 64;
// How long a reliable write may wait for a slow reader's acknowledgements before failing.
constexpr dds_duration_t kMaxBlocking = DDS_MSECS(10);

}  // namespace

Qos topic_qos(Topic topic, bool reliable_state) {
  Qos qos(dds_create_qos());
  switch (topic) {
    case Topic::kState:
      // Subscribers want the newest state; a lost one is replaced within one publish period.
      if (reliable_state) {
        dds_qset_reliability(qos.get(), DDS_RELIABILITY_RELIABLE, kMaxBlocking);
      } else {
        dds_qset_reliability(qos.get(), DDS_RELIABILITY_BEST_EFFORT, 0);
      }
      dds_qset_history(qos.get(), DDS_HISTORY_KEEP_LAST, 1);
      break;
    case Topic::kWrench:
    case Topic::kControl:
    case Topic::kAccepted:  // a recorder wants every one, as the server received them
      dds_qset_reliability(qos.get(), DDS_RELIABILITY_RELIABLE, kMaxBlocking);
      dds_qset_history(qos.get(), DDS_HISTORY_KEEP_LAST, kCommandDepth);
      break;
    case Topic::kControlReply:
      dds_qset_reliability(qos.get(), DDS_RELIABILITY_RELIABLE, kMaxBlocking);
      dds_qset_history(qos.get(), DDS_HISTORY_KEEP_LAST, kReplyDepth);
      break;
    case Topic::kStats:
      dds_qset_reliability(qos.get(), DDS_RELIABILITY_RELIABLE, kMaxBlocking);
      dds_qset_history(qos.get(), DDS_HISTORY_KEEP_LAST, 1);
      break;
    case Topic::kScene:
      // Late joiners get the scene from the writer's history.
      dds_qset_reliability(qos.get(), DDS_RELIABILITY_RELIABLE, kMaxBlocking);
      dds_qset_durability(qos.get(), DDS_DURABILITY_TRANSIENT_LOCAL);
      dds_qset_history(qos.get(), DDS_HISTORY_KEEP_LAST, 1);
      break;
  }
  return qos;
}

Qos reader_qos(Topic topic, bool reliable_state, int state_history) {
  Qos qos = topic_qos(topic, reliable_state);
  if (topic == Topic::kState) dds_qset_history(qos.get(), DDS_HISTORY_KEEP_LAST, state_history);
  return qos;
}

}  // namespace rigid::transport::dds
