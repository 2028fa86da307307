// rigid-sim's work: run a scene for a duration as fast as possible, optionally writing the states
// to a CSV file, and summarise what happened (drift of the conserved quantities, cost).
#pragma once

#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

#include "physics/world.hpp"
#include "scene/scene.hpp"
#include "sim/sim_options.hpp"

namespace rigid::sim {

struct BodySummary {
  std::string name;
  physics::BodyMotion motion = physics::BodyMotion::kTumbling;
  physics::Vec3 p_final = physics::Vec3::Zero();
  // Kinetic energy and angular momentum about the centre of mass (in W), at t = 0 and at the end.
  double ke0 = 0.0, ke = 0.0;
  physics::Vec3 L0 = physics::Vec3::Zero(), L = physics::Vec3::Zero();
};

struct RunSummary {
  std::string scene;
  std::string integrator;
  bool default_integrator = false;
  double dt = 0.0;
  std::int64_t steps = 0;
  double t_end = 0.0;
  std::vector<BodySummary> bodies;
  double energy0 = 0.0, energy = 0.0;       // World::total_energy at t = 0 and at the end
  double wall_seconds = 0.0;                // the whole run, output included
  double step_seconds = 0.0;                // inside World::step only
  std::string csv;                          // empty without --csv
  std::int64_t csv_rows = 0;                // data rows, header excluded
  std::int64_t every = 0;                   // ticks between CSV rows
  std::string contacts_csv;                 // empty without --contacts-csv
  std::int64_t contact_events = 0;          // over the run
  std::int64_t contact_events_dropped = 0;  // beyond the physics' 4096 a tick
};

// Runs `scene` as `options` say (duration, integrator and dt overrides, CSV). The number of steps
// is duration / dt rounded to the nearest integer. Throws UsageError when the options do not fit
// the scene, std::runtime_error when the CSV cannot be written (and then leaves no partial file).
RunSummary run(const scene::Scene& scene, const SimOptions& options);

// The end-of-run table.
void print_summary(std::ostream& out, const RunSummary& summary);

// --list-integrators: name, order, symplectic, gyroscopic, summary; the default marked with '*'.
void print_integrators(std::ostream& out);

}  // namespace rigid::sim
