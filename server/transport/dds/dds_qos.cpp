#include "transport/dds/dds_qos.hpp"

namespace rigid::transport::dds {
namespace {

// Commands are kept, not just the latest, so a burst from one controller is not collapsed; past
// this many unread ones the oldest go, so a flood never blocks the controller's writer.
constexpr int kCommandDepth = 256;
constexpr int kReplyDepth = 64;
// Contact events come one message per tick that has any: a burst (bodies landing tick after tick,
// a lockstep step request sent back to back) is kept for a subscriber a little behind, up to this
// many ticks; each message is at most 4096 events (~300 KB).
constexpr int kContactDepth = 64;
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
    case Topic::kEdit:
    case Topic::kAccepted:  // a recorder wants every one, as the server received them
      dds_qset_reliability(qos.get(), DDS_RELIABILITY_RELIABLE, kMaxBlocking);
      dds_qset_history(qos.get(), DDS_HISTORY_KEEP_LAST, kCommandDepth);
      break;
    case Topic::kContacts:
      // Every event matters (an impact is not repeated as a state is), so reliable; the writer
      // waits at most kMaxBlocking for a slow reader, then the sample is dropped and counted.
      dds_qset_reliability(qos.get(), DDS_RELIABILITY_RELIABLE, kMaxBlocking);
      dds_qset_history(qos.get(), DDS_HISTORY_KEEP_LAST, kContactDepth);
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
