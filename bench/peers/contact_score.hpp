// Scores a contact run from copy 0's states after every step (and, for an engine that locates
// them, its events), by one set of rules for every engine: what peer_contacts writes per
// (case, engine mode, dt). The rules are README.md's "Contacts: what is measured".
#pragma once

#include <iosfwd>
#include <span>
#include <string>
#include <vector>

#include "contact_case.hpp"
#include "contact_engine.hpp"

namespace rigid::bench::peers {

// One run's figures (NaN where a figure does not apply to the case or the run lacks it; +inf
// where the run never does what is timed, e.g. never comes to rest).
struct ContactRow {
  int impacts = 0;        // impacts found (approached at kRestSpeed or more), at most 10 x 12
  int exact_impacts = 0;  // the closed form's, over the same duration
  double first_impact_error = kNaN;  // s, run minus closed form
  double later_impact_error = kNaN;  // s, the largest |error| of impacts 2..12 both have
  double max_penetration = kNaN;     // m, of the body's lowest point below the plane
  double apex_error = kNaN;       // m: after the 12th impact (elastic), largest |.| of the first 3
  double energy_error = kNaN;     // relative, at the apex after the 12th impact (elastic)
  double max_energy_rise = kNaN;  // relative to the start's energy, over non-penetrating states
  std::string rest_rule;          // "event" or "speed" (see README.md)
  double rest_time = kNaN;        // s, by rest_rule
  // s: an event against the closed form's rest; the speed rule against what it finds on the exact
  // motion sampled at the same dt.
  double rest_time_error = kNaN;
  double stop_distance_error = kNaN;  // m (sliding)
  double drift = kNaN;                // m, the largest corner displacement after kSettleTime
  double final_tilt = kNaN;           // rad (cubes)
  int max_points = 0;                 // the most contact points the engine reported in a step
  bool blown_up = false;
};

class ContactScorer {
 public:
  // `events`: take impacts and rest from the engine's located events instead of the states.
  ContactScorer(const ContactCase& c, double dt, bool events);
  // After step n (1-based): copy 0's state at n dt, its contact and its events over the step.
  void observe(long n, const BodyState& s, const StepContact& contact,
               std::span<const LocatedEvent> events);
  ContactRow result() const;
  bool failed() const { return failed_; }

 private:
  void impact(double t);
  void close_flight();

  const ContactCase& c_;
  const ClosedForm exact_;
  const double dt_;
  const bool events_;
  ContactRow row_;
  BodyState prev_;
  double E0_ = 0, E_min_ = 0;
  bool failed_ = false;
  std::vector<double> impacts_;
  // The flight after the latest impact: the non-penetrating state nearest its apex (smallest
  // |vz|), and whether there is one.
  BodyState apex_state_;
  bool have_apex_ = false;
  std::vector<double> apex_heights_, apex_energies_;  // after impacts 1, 2, ...
  double approach_ = 0;            // fastest descent since the last reversal (state rule)
  double last_fast_ = 0;           // time of the last state at kRestSpeed or more (speed rule)
  double rest_event_ = kNaN;       // the last resting event not followed by another event
  double speed_rule_rest_ = kNaN;  // what the speed rule finds on the exact motion at dt
  std::vector<Vec3> settled_corners_;
  BodyState last_;
};

// The CSV peer_contacts writes, one row per (case, engine mode, dt).
void write_contact_csv_header(std::ostream& os);
// Costs in ns per body-step: the whole run, its steps after kSettleTime, and the same body without
// the plane over the whole run.
void write_contact_csv_row(std::ostream& os, const ContactCase& c, const std::string& engine_mode,
                           double dt, long steps, const ContactRow& r, double ns_per_body_step,
                           double settled_ns_per_body_step, double free_ns_per_body_step);

}  // namespace rigid::bench::peers
