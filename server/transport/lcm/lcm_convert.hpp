// Plain messages (messages.hpp) <-> lcm-gen's C++ types (msgs/rigid.lcm), through the field lists
// both buses share (transport/wire_fields.hpp), plus the count fields only LCM's types have
// (num_bodies, ...). Copies reuse the destination's storage. Only the LCM adapter and codec include
// this.
#pragma once

#include <cstddef>
#include <rigid_lcm/AcceptedCommand.hpp>
#include <rigid_lcm/ContactEvents.hpp>
#include <rigid_lcm/Control.hpp>
#include <rigid_lcm/ControlReply.hpp>
#include <rigid_lcm/Edit.hpp>
#include <rigid_lcm/SceneInfo.hpp>
#include <rigid_lcm/Stats.hpp>
#include <rigid_lcm/WorldState.hpp>
#include <rigid_lcm/Wrench.hpp>

#include "rigid/messages.hpp"
#include "transport/decode_status.hpp"
#include "transport/wire_fields.hpp"

namespace rigid::transport::lcm {

// The lcm-gen type carrying each plain message.
template <class Plain>
struct LcmTypeOf;
template <>
struct LcmTypeOf<StateFrame> {
  using type = rigid_lcm::WorldState;
};
template <>
struct LcmTypeOf<WrenchCommand> {
  using type = rigid_lcm::Wrench;
};
template <>
struct LcmTypeOf<ControlCommand> {
  using type = rigid_lcm::Control;
};
template <>
struct LcmTypeOf<ControlReply> {
  using type = rigid_lcm::ControlReply;
};
template <>
struct LcmTypeOf<StatsReport> {
  using type = rigid_lcm::Stats;
};
template <>
struct LcmTypeOf<SceneDescription> {
  using type = rigid_lcm::SceneInfo;
};
template <>
struct LcmTypeOf<AcceptedCommand> {
  using type = rigid_lcm::AcceptedCommand;
};
template <>
struct LcmTypeOf<ContactEvents> {
  using type = rigid_lcm::ContactEvents;
};
template <>
struct LcmTypeOf<EditCommand> {
  using type = rigid_lcm::Edit;
};

// The count fields for n rows (bodies, refused sources, events; bodies and parts); a message
// without any has none to set.
void set_counts(std::size_t n, rigid_lcm::WorldState& out);
void set_counts(std::size_t n, rigid_lcm::Stats& out);
void set_counts(const wire::SceneRows& n, rigid_lcm::SceneInfo& out);
void set_counts(std::size_t n, rigid_lcm::ContactEvents& out);
template <class Lcm>
void set_counts(std::size_t /*n*/, Lcm& /*out*/) {}

// The rows a received message holds, or false when its count fields disagree (e.g. num_xyz !=
// 3 * num_bodies) or exceed the bounds.
bool rows(const rigid_lcm::WorldState& in, std::size_t& n);
bool rows(const rigid_lcm::Stats& in, std::size_t& n);
bool rows(const rigid_lcm::SceneInfo& in, wire::SceneRows& n);
bool rows(const rigid_lcm::ContactEvents& in, std::size_t& n);
template <class Lcm>
bool rows(const Lcm& /*in*/, std::size_t& n) {
  n = 0;
  return true;
}

// false: the per-body arrays disagree with the body count, or are too long for LCM's int32 counts.
template <class Plain>
bool to_lcm(const Plain& in, typename LcmTypeOf<Plain>::type& out) {
  typename wire::RowsOf<Plain>::type n{};
  if (!wire::rows(in, n)) return false;
  set_counts(n, out);
  return wire::encode(in, out, n);
}

// kInconsistentLengths when the count fields disagree.
template <class Plain>
DecodeStatus from_lcm(const typename LcmTypeOf<Plain>::type& in, Plain& out) {
  typename wire::RowsOf<Plain>::type n{};
  if (!rows(in, n)) return DecodeStatus::kInconsistentLengths;
  wire::decode(in, out, n);
  return DecodeStatus::kOk;
}

}  // namespace rigid::transport::lcm
