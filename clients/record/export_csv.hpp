// rigid-record export: the states in a recording, or in an lcm-logger log of rigidd's channels, as
// rigid-sim's CSV (t,body,x,...,wz; a row per body per state), written to OUT.tmp and renamed
// when complete (an existing OUT is refused unless --force). Bodies are named from the scene the
// file holds (SceneInfo), else by id.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <map>
#include <string>

#include "record/record_options.hpp"

namespace rigid::record {

// Returns the exit status (1: the input cannot be read, is a journal or holds no states, or the
// CSV cannot be written; nothing is written then).
int export_csv(const RecordOptions& options, std::ostream& out, std::ostream& err);

// The prefix of rigidd's channels in an LCM log whose channels (with their event counts) are
// `seen`: --prefix's, else "" if the unprefixed state channel is there, else the one prefix the
// log holds. Throws clients::UsageError (several prefixes) or common::LogFileError (none).
std::string lcm_log_prefix(const RecordOptions& options,
                           const std::map<std::string, std::int64_t>& seen);

// Why a journal is refused by export (it holds no states): one line naming `path`.
std::string journal_has_no_states(const std::string& path);

// Throws common::LogFileError if `path` exists and not `force` (export's outputs, like record's,
// are not overwritten unless asked).
void refuse_existing(const std::string& path, bool force);

}  // namespace rigid::record
