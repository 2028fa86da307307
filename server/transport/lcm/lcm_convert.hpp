// Plain messages (messages.hpp) <-> lcm-gen's C++ types (msgs/rigid.lcm). Copies reuse the
// destination's storage. Only the LCM adapter and codec include this.
#pragma once

#include <rigid_lcm/AcceptedCommand.hpp>
#include <rigid_lcm/Control.hpp>
#include <rigid_lcm/ControlReply.hpp>
#include <rigid_lcm/SceneInfo.hpp>
#include <rigid_lcm/Stats.hpp>
#include <rigid_lcm/WorldState.hpp>
#include <rigid_lcm/Wrench.hpp>

#include "rigid/messages.hpp"
#include "transport/decode_status.hpp"

namespace rigid::transport::lcm {

// false: the per-body arrays disagree with the body count, or are too long for LCM's int32 counts.
bool to_lcm(const StateFrame& in, rigid_lcm::WorldState& out);
bool to_lcm(const WrenchCommand& in, rigid_lcm::Wrench& out);
bool to_lcm(const ControlCommand& in, rigid_lcm::Control& out);
bool to_lcm(const ControlReply& in, rigid_lcm::ControlReply& out);
bool to_lcm(const StatsReport& in, rigid_lcm::Stats& out);
bool to_lcm(const SceneDescription& in, rigid_lcm::SceneInfo& out);
bool to_lcm(const AcceptedCommand& in, rigid_lcm::AcceptedCommand& out);

// kInconsistentLengths when the count fields disagree (e.g. num_xyz != 3 * num_bodies).
DecodeStatus from_lcm(const rigid_lcm::WorldState& in, StateFrame& out);
DecodeStatus from_lcm(const rigid_lcm::Wrench& in, WrenchCommand& out);
DecodeStatus from_lcm(const rigid_lcm::Control& in, ControlCommand& out);
DecodeStatus from_lcm(const rigid_lcm::ControlReply& in, ControlReply& out);
DecodeStatus from_lcm(const rigid_lcm::Stats& in, StatsReport& out);
DecodeStatus from_lcm(const rigid_lcm::SceneInfo& in, SceneDescription& out);
DecodeStatus from_lcm(const rigid_lcm::AcceptedCommand& in, AcceptedCommand& out);

}  // namespace rigid::transport::lcm
