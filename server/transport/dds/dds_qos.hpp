// The QoS of each rigid topic. Writers and readers of a topic use the same QoS, so they always
// match (a best-effort writer never matches a reliable reader).
#pragma once

#include "transport/dds/dds_entity.hpp"
#include "transport/topic.hpp"

namespace rigid::transport::dds {

// reliable_state: rigid/state reliable instead of best-effort. Both ends must agree (a best-effort
// reader also matches a reliable writer, so clients may keep the default).
Qos topic_qos(Topic topic, bool reliable_state);

// A reader's QoS: the topic's, except that a state reader keeps `state_history` unread states
// instead of the newest one (history depth is not matched between writer and reader). rigidd
// paces the states of a step request (and every state in lockstep) to its publishers, which send
// them back to back: a subscriber whose thread is a little slower than rigidd for a moment would
// otherwise see only the last of a burst. A subscriber more than this many states behind still
// gets the newest ones; the memory is at most that many states (28 MB for 1000 bodies at the
// default, kStateReaderDepth).
inline constexpr int kStateReaderDepth = 256;
Qos reader_qos(Topic topic, bool reliable_state, int state_history = kStateReaderDepth);

}  // namespace rigid::transport::dds
