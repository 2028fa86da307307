// The QoS of each rigid topic. Writers and readers of a topic use the same QoS, so they always
// match (a best-effort writer never matches a reliable reader).
#pragma once

#include "transport/dds/dds_entity.hpp"
#include "transport/topic.hpp"

namespace rigid::transport::dds {

// reliable_state: rigid/state reliable instead of best-effort. Both ends must agree (a best-effort
// reader also matches a reliable writer, so clients may keep the default).
Qos topic_qos(Topic topic, bool reliable_state);

}  // namespace rigid::transport::dds
