// rigid-record export: the states in a recording, or in an lcm-logger log of rigidd's channels, as
// rigid-sim's CSV (t,body,x,...,wz; a row per body per state), written to OUT.tmp and renamed
// when complete. Bodies are named from the scene the file holds (SceneInfo), else by id.
#pragma once

#include <iosfwd>

#include "record/record_options.hpp"

namespace rigid::record {

// Returns the exit status (1: the input cannot be read or the CSV written).
int export_csv(const RecordOptions& options, std::ostream& out, std::ostream& err);

}  // namespace rigid::record
