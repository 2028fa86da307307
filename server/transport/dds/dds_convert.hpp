// Plain messages (messages.hpp) <-> idlc's C types (msgs/rigid.idl). Only the DDS adapter and
// codec include this.
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

namespace rigid::transport::dds {

// Storage some borrowed views need (SceneInfo's array of C strings and its shape kinds as int32).
struct BorrowScratch {
  std::vector<std::array<char, kMaxNameLength + 1>> names;  // string<128>: char[129] each
  std::vector<std::int32_t> shape_kinds;
  std::vector<std::array<char, kMaxSenderLength + 1>> senders;
  std::vector<std::array<char, kMaxReasonLength + 1>> reasons;
  std::vector<std::int64_t> counts;
};

// false: the per-body arrays disagree with the body count (or exceed DDS's uint32 lengths).
bool borrow(const StateFrame& in, BorrowScratch& scratch, rigid_WorldState& out);
bool borrow(const WrenchCommand& in, BorrowScratch& scratch, rigid_Wrench& out);
bool borrow(const ControlCommand& in, BorrowScratch& scratch, rigid_Control& out);
bool borrow(const ControlReply& in, BorrowScratch& scratch, rigid_ControlReply& out);
bool borrow(const StatsReport& in, BorrowScratch& scratch, rigid_Stats& out);
bool borrow(const SceneDescription& in, BorrowScratch& scratch, rigid_SceneInfo& out);
bool borrow(const AcceptedCommand& in, BorrowScratch& scratch, rigid_AcceptedCommand& out);

// Copies into `out`, reusing its storage. kInconsistentLengths when per-body sequences disagree.
DecodeStatus copy_from(const rigid_WorldState& in, StateFrame& out);
DecodeStatus copy_from(const rigid_Wrench& in, WrenchCommand& out);
DecodeStatus copy_from(const rigid_Control& in, ControlCommand& out);
DecodeStatus copy_from(const rigid_ControlReply& in, ControlReply& out);
DecodeStatus copy_from(const rigid_Stats& in, StatsReport& out);
DecodeStatus copy_from(const rigid_SceneInfo& in, SceneDescription& out);
DecodeStatus copy_from(const rigid_AcceptedCommand& in, AcceptedCommand& out);

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

}  // namespace rigid::transport::dds
