// rigid-record info: what a log file holds (recording or journal; an lcm-logger log too): its
// header, its records by kind, the ticks and time it spans, and how it ends: cleanly, without its
// closing record, or in a damaged tail (where and why), which is reported, not an error.
#pragma once

#include <iosfwd>
#include <string>

namespace rigid::record {

// Returns the exit status: 0 readable (damaged tail or not), 1 not a log file or unreadable.
int info(const std::string& path, std::ostream& out, std::ostream& err);

}  // namespace rigid::record
