// rigid-record export --mcap: a recording (or an lcm-logger log of rigidd's channels) as an MCAP
// file (mcap_writer.hpp) that the Foxglove app opens: its 3D panel shows the bodies, its Plot
// panel their states. Channels, all protobuf with their schemas embedded (a FileDescriptorSet):
//
//   /rigid/transforms  foxglove.FrameTransforms  per state: "world" -> body name, pose exact
//   /rigid/bodies      foxglove.SceneUpdate      per body an entity in its own frame: its shape
//   /rigid/state       rigid.msgs.StateRecord    the states as recorded (msgs/rigid.proto)
//   /rigid/scene       rigid.msgs.SceneRecord    the scene, and each change of it
//   /rigid/stats       rigid.msgs.StatsRecord    rigidd's Stats
//   /rigid/accepted    rigid.msgs.CommandRecord  the accepted commands
//
// Times: log_time is when the recorder received the message on the wall clock (LogHeader's
// start_unix_ns + the record's recorded_ns; lcm-logger's timestamp for its logs), the same axis
// for every channel, in the order the recording holds them. publish_time is rigidd's wall clock
// when it published a state (stamp_ns) or an accepted command, else log_time. Foxglove plays by
// log_time; the transforms' and entities' own timestamps equal their message's log_time so that
// its 3D panel finds them at the time it plays. Sim time is in the StateRecord (sim_time).
//
// Written to OUT.tmp and renamed when complete; an existing OUT is refused unless --force.
#pragma once

#include <iosfwd>

#include "record/record_options.hpp"

namespace rigid::record {

// Returns the exit status (1: the input cannot be read or holds no states, or OUT cannot be
// written; 2: a bad command line, e.g. several prefixes in an LCM log and no --prefix).
int export_mcap(const RecordOptions& options, std::ostream& out, std::ostream& err);

}  // namespace rigid::record
