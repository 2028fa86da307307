// One (case, peer mode, step) measured exactly as bench/work_precision measures ours: an accuracy
// run of `copies` bodies observing body 0 after every step, scored by the shared Scorer, and cost
// runs of `copies` bodies timed in thread CPU time (median of repeats).
#pragma once

#include <string>

#include "peer_engine.hpp"

namespace rigid::bench::peers {

// Accuracy figures of one run (infinite errors when it blew up).
Row accuracy_run(const PeerEngine& engine, const Case& c, const std::string& mode, double dt,
                 const Reference& reference, int copies = kCopies);

// Median thread CPU time per body-step (ns) over `repeats` fresh worlds of `copies` bodies.
double cost_run(const PeerEngine& engine, const Case& c, const std::string& mode, double dt,
                int repeats, int copies = kCopies);

}  // namespace rigid::bench::peers
