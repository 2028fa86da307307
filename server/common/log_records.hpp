// The messages rigid exchanges (rigid/messages.hpp) as log records (msgs/rigid.proto, "Log
// records") and back, for rigid-record's recordings and rigidd's journal. Numbers are copied
// exactly (doubles stay doubles), so a state read back from a file equals the one received.
#pragma once

#include <cstdint>

#include "rigid.pb.h"
#include "rigid/messages.hpp"

namespace rigid::common {

// recorded_ns: CLOCK_MONOTONIC since the file was started (the pace `play` replays at).
void to_record(const rigid::StateFrame& in, std::int64_t recorded_ns, msgs::StateRecord& out);
void to_record(const rigid::SceneDescription& in, std::int64_t recorded_ns, msgs::SceneRecord& out);
void to_record(const rigid::StatsReport& in, std::int64_t recorded_ns, msgs::StatsRecord& out);
void to_record(const rigid::AcceptedCommand& in, std::int64_t recorded_ns,
               msgs::CommandRecord& out);
void to_record(const rigid::ContactEvents& in, std::int64_t recorded_ns, msgs::ContactRecord& out);

// false: the record's per-body arrays disagree with its body count (`out` is then unspecified).
bool from_record(const msgs::StateRecord& in, rigid::StateFrame& out);
bool from_record(const msgs::SceneRecord& in, rigid::SceneDescription& out);
void from_record(const msgs::StatsRecord& in, rigid::StatsReport& out);
void from_record(const msgs::CommandRecord& in, rigid::AcceptedCommand& out);
// false: the record's per-event arrays disagree with its event count, or it holds more than
// rigid::kMaxContactEvents.
bool from_record(const msgs::ContactRecord& in, rigid::ContactEvents& out);

}  // namespace rigid::common
