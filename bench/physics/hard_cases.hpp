// The hard cases of the work-precision benchmarks, their oracles, and the scoring of a run: shared
// by bench/work_precision (our integrators) and the peer drivers (MuJoCo, Bullet, ODE), so that
// every engine is scored on the same cases, against the same references, by the same code.
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

#include "physics/spec.hpp"
#include "physics/world.hpp"
#include "reference.hpp"  // server/oracle: the independent oracle

namespace rigid::bench {

using physics::BodySpec;
using physics::BodyState;
using physics::Frame;
using physics::LoadSpec;
using physics::Quat;
using physics::Vec3;
namespace ref = rigid::test;

// Bodies stepped together when timing (cost = CPU time / (steps * copies)): 32 in a full run,
// kQuickCopies with --quick, where fewer copies make the slow peers' sweeps affordable.
inline constexpr int kCopies = 32;
inline constexpr int kQuickCopies = 4;

// One hard case: a single body, its loads, and the oracle.
struct Case {
  std::string name;
  std::string description;
  double duration = 5.0;
  BodySpec body;
  std::vector<LoadSpec> loads;  // on body 0; replicated for each copy
  ref::RefBody oracle;          // the same body for the long-double reference
  long reference_steps = 1000000;
  bool closed_form_drag = false;  // stiff drag: scored against the closed form along the path
  bool conservative = true;       // energy and momentum (or energy) are invariants to report
  bool torque_free = false;       // scored against the quad-precision Taylor series
};

std::vector<Case> hard_cases();
// The steps of the sweep: 1/60 s to 1/10000 s (four of them with quick).
std::vector<double> sweep_steps(bool quick);
// Ours are swept from 1/10 s: a step of ours costs 3-60x less than a peer's, so that our curves
// reach as far down the cost axis as the peers' cheapest runs (1/60 s), where the report checks
// that our curves lie below theirs.
std::vector<double> our_sweep_steps(bool quick);
// The gravity a case's world uses.
Vec3 gravity_of(const Case& c);
// Our world for a case: `copies` identical copies of its body and loads, stepped by `integrator`.
physics::WorldSpec world_spec(const Case& c, const std::string& integrator, double dt, int copies);

struct Reference {
  ref::RefState state;  // body 0 at the end of the case
  std::string name;     // how it was obtained, for the report
};
// With a cache file, a reference already in it (same case, description and mode) is read back
// instead of computed, and a computed one is added: the drivers of one report run share them.
Reference compute_reference(const Case& c, bool quick, const std::string& cache = "");

// One run's accuracy figures (NaN where a figure does not apply to the case).
struct Row {
  double err_q = NAN, err_w = NAN, err_x = NAN, energy = NAN, momentum = NAN;
};

// Scores body 0 of a run from its states alone, so that any engine can be scored alike: energy
// (kinetic + gravity + the potential of constant world forces at points) and angular momentum
// are computed here from the case's mass and inertia.
class Scorer {
 public:
  Scorer(const Case& c, const Reference& r, long steps);
  // Called after every step with body 0's state at time t.
  void observe(long step, double t, const BodyState& s);
  Row result(const BodyState& final_state) const;
  bool failed() const { return failed_; }  // non-finite state: the run blew up

 private:
  double energy(const BodyState& s) const;
  Vec3 momentum(const BodyState& s) const;
  const Case& case_;
  const Reference& ref_;
  long steps_, every_;
  double E0_ = 0, worst_E_ = 0, worst_L_ = 0, worst_x_ = 0;
  Vec3 L0_ = Vec3::Zero();
  bool started_ = false, failed_ = false;
};

// Whether a run has blown up at this step, by one rule for every engine, ours included: a
// non-finite state, or MuJoCo's own bound on a sane value (mjMAXVAL = 1e10) exceeded by a position,
// a velocity or an acceleration (here the change of velocity over the step just taken, per dt).
// MuJoCo resets a model past that bound; without the common rule an explicit drag at c dt / m
// slightly above 2 (stiff drag at 1/240 s) would read as a blow-up in MuJoCo but as a finite,
// meaningless error growing ~|1 - c dt / m|^n in Bullet, ODE and ours.
bool blown_up(const BodyState& s, const BodyState& prev, double dt);
// The state a blown-up run reports from then on: NaN, which the Scorer counts as a failure.
BodyState nan_state();

// CPU time of the calling thread (ns): what the cost columns measure.
double thread_cpu_ns();
// The CSV the plot script reads.
void write_csv_header(std::ostream& os);
void write_csv_row(std::ostream& os, const Case& c, const std::string& integrator, double dt,
                   const Row& row, double ns_per_body_step, const std::string& reference);
// Machine, compiler, flags, date: what every figure must carry; and how the costs were taken
// (copies = 0: the caller says it in `extra`).
void write_meta(const std::string& path, bool quick, int copies, int repeats,
                const std::string& extra = "");

}  // namespace rigid::bench
