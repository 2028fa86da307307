// What both record fuzzers (fuzz_record_file, fuzz_log_record) do with a LogRecord that parsed:
// convert it as rigid-record and rigid-sim --replay do (common/log_records.hpp), and check that
// the conversion is stable: a record converted to a message and back, twice, gives the same bytes.
#pragma once

#include <google/protobuf/stubs/logging.h>

#include <string>
#include <type_traits>

#include "common/log_records.hpp"
#include "fuzz_require.hpp"
#include "rigid.pb.h"

namespace rigid::fuzz {

// For LLVMFuzzerInitialize: protobuf logs every string field that is not UTF-8 (a parse failure
// the reader reports as damage), which would bury libFuzzer's output. Fatal messages still abort.
inline void quiet_protobuf() {
  google::protobuf::SetLogHandler(nullptr);
}

template <class Plain, class Record>
void check_conversion(const Record& in) {
  Plain plain;
  // from_record refuses (false) records whose per-body arrays disagree: the tools skip them.
  if constexpr (std::is_same_v<decltype(common::from_record(in, plain)), bool>) {
    if (!common::from_record(in, plain)) return;
  } else {
    common::from_record(in, plain);
  }
  Record back;
  common::to_record(plain, in.recorded_ns(), back);
  Plain again;
  if constexpr (std::is_same_v<decltype(common::from_record(back, again)), bool>) {
    require(common::from_record(back, again), "a record written from a message reads back");
  } else {
    common::from_record(back, again);
  }
  Record twice;
  common::to_record(again, in.recorded_ns(), twice);
  require(back.SerializeAsString() == twice.SerializeAsString(),
          "converting a record to a message and back is stable");
}

inline void check_record(const msgs::LogRecord& record) {
  switch (record.record_case()) {
    case msgs::LogRecord::kHeader:
      check_conversion<rigid::SceneDescription>(record.header().scene());
      break;
    case msgs::LogRecord::kState:
      check_conversion<rigid::StateFrame>(record.state());
      break;
    case msgs::LogRecord::kScene:
      check_conversion<rigid::SceneDescription>(record.scene());
      break;
    case msgs::LogRecord::kStats:
      check_conversion<rigid::StatsReport>(record.stats());
      break;
    case msgs::LogRecord::kCommand:
      check_conversion<rigid::AcceptedCommand>(record.command());
      break;
    case msgs::LogRecord::kContacts:
      check_conversion<rigid::ContactEvents>(record.contacts());
      break;
    case msgs::LogRecord::kStateHash:
    case msgs::LogRecord::kContactHash:
    case msgs::LogRecord::kGap:
    case msgs::LogRecord::kEnd:
    case msgs::LogRecord::RECORD_NOT_SET:
      // Plain numbers, read field by field by their users.
      break;
  }
}

}  // namespace rigid::fuzz
