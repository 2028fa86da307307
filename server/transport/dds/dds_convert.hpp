// Plain messages (messages.hpp) <-> idlc's C types (msgs/rigid.idl), through the field lists both
// buses share (transport/wire_fields.hpp). Only the DDS adapter and codec include this.
//
// Outgoing messages are borrowed, not copied: the C struct's sequences and strings point into the
// plain message, which must outlive the write (dds_write serializes before it returns). So
// publishing a state copies nothing and allocates nothing on our side.
#pragma once

#include <rigid.h>

#include <array>
#include <cstdint>
#include <vector>

#include "rigid/messages.hpp"
#include "transport/decode_status.hpp"
#include "transport/topic.hpp"
#include "transport/wire_fields.hpp"

namespace rigid::transport::dds {

// The idlc type and topic carrying each plain message.
template <class Plain>
struct DdsTypeOf;
template <>
struct DdsTypeOf<StateFrame> {
  using type = rigid_WorldState;
  static constexpr const dds_topic_descriptor_t* descriptor = &rigid_WorldState_desc;
  static constexpr Topic topic = Topic::kState;
};
template <>
struct DdsTypeOf<WrenchCommand> {
  using type = rigid_Wrench;
  static constexpr const dds_topic_descriptor_t* descriptor = &rigid_Wrench_desc;
  static constexpr Topic topic = Topic::kWrench;
};
template <>
struct DdsTypeOf<ControlCommand> {
  using type = rigid_Control;
  static constexpr const dds_topic_descriptor_t* descriptor = &rigid_Control_desc;
  static constexpr Topic topic = Topic::kControl;
};
template <>
struct DdsTypeOf<ControlReply> {
  using type = rigid_ControlReply;
  static constexpr const dds_topic_descriptor_t* descriptor = &rigid_ControlReply_desc;
  static constexpr Topic topic = Topic::kControlReply;
};
template <>
struct DdsTypeOf<StatsReport> {
  using type = rigid_Stats;
  static constexpr const dds_topic_descriptor_t* descriptor = &rigid_Stats_desc;
  static constexpr Topic topic = Topic::kStats;
};
template <>
struct DdsTypeOf<SceneDescription> {
  using type = rigid_SceneInfo;
  static constexpr const dds_topic_descriptor_t* descriptor = &rigid_SceneInfo_desc;
  static constexpr Topic topic = Topic::kScene;
};
template <>
struct DdsTypeOf<AcceptedCommand> {
  using type = rigid_AcceptedCommand;
  static constexpr const dds_topic_descriptor_t* descriptor = &rigid_AcceptedCommand_desc;
  static constexpr Topic topic = Topic::kAccepted;
};
template <>
struct DdsTypeOf<ContactEvents> {
  using type = rigid_ContactEvents;
  static constexpr const dds_topic_descriptor_t* descriptor = &rigid_ContactEvents_desc;
  static constexpr Topic topic = Topic::kContacts;
};

template <>
struct DdsTypeOf<EditCommand> {
  using type = rigid_Edit;
  static constexpr const dds_topic_descriptor_t* descriptor = &rigid_Edit_desc;
  static constexpr Topic topic = Topic::kEdit;
};

// Storage some borrowed views need (strings as char arrays, shape kinds as int32): one per writer.
using BorrowScratch = wire::Scratch;

// The rows (bodies, refused sources, static parts, events) a received sample holds, or false when
// its sequences' lengths disagree.
bool rows(const rigid_WorldState& in, std::size_t& n);
bool rows(const rigid_Stats& in, std::size_t& n);
bool rows(const rigid_SceneInfo& in, wire::SceneRows& n);
bool rows(const rigid_ContactEvents& in, std::size_t& n);
template <class Dds>
bool rows(const Dds& /*in*/, std::size_t& n) {
  n = 0;
  return true;
}

// Fills `out` from `in`. false: the per-body arrays disagree with the body count (or exceed DDS's
// uint32 lengths), or a string is longer than its bound.
template <class Plain>
bool borrow(const Plain& in, BorrowScratch& scratch, typename DdsTypeOf<Plain>::type& out) {
  typename wire::RowsOf<Plain>::type n{};
  return wire::rows(in, n) && wire::encode(in, out, n, &scratch);
}

// Copies into `out`, reusing its storage. kInconsistentLengths when per-body sequences disagree.
template <class Plain>
DecodeStatus copy_from(const typename DdsTypeOf<Plain>::type& in, Plain& out) {
  typename wire::RowsOf<Plain>::type n{};
  if (!rows(in, n)) return DecodeStatus::kInconsistentLengths;
  wire::decode(in, out, n);
  return DecodeStatus::kOk;
}

}  // namespace rigid::transport::dds
