// One (contact case, engine mode, dt) measured: an accuracy run of one copy scored by the
// ContactScorer, and cost runs of many copies timed in thread CPU time.
#pragma once

#include <string>

#include "contact_engine.hpp"
#include "contact_score.hpp"

namespace rigid::bench::peers {

// Copy 0 of a one-copy world, recorded and scored after every step.
ContactRow contact_accuracy_run(const ContactEngine& engine, const ContactCase& c,
                                const std::string& mode, double dt);

// Thread CPU time per body-step (ns) of fresh worlds of `copies` copies, each stepped for the
// case's duration (built outside the timing, not recording), as many worlds as it takes to time
// at least `min_ns` in all (a run of a cheap engine at a coarse step is too short to time alone):
// over the whole runs, and over their steps after kSettleTime alone (what a body costs once it has
// landed, stopped or come to rest).
struct ContactCost {
  double ns_per_body_step = 0;
  double settled_ns_per_body_step = 0;
};
ContactCost contact_cost_run(const ContactEngine& engine, const ContactCase& c,
                             const std::string& mode, double dt, int copies, double min_ns = 0);

// The number of steps a case takes at dt.
long contact_steps(const ContactCase& c, double dt);

}  // namespace rigid::bench::peers
