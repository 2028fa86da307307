// The hard cases of the work-precision benchmarks, their oracles, and the scoring of a run: shared
// by bench/work_precision (our integrators) and the peer drivers (MuJoCo, Bullet, ODE), so that
// every engine is scored on the same cases, against the same references, by the same code.
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

#include "physics/spec.hpp"
#include "physics/world.hpp"
#include "reference.hpp"  // tests/physics: the independent oracles

namespace rigid::bench {

using physics::BodySpec;
using physics::BodyState;
using physics::Frame;
using physics::LoadSpec;
using physics::Quat;
using physics::Vec3;
namespace ref = rigid::test;

// Bodies stepped together when timing (cost = CPU time / (steps * kCopies)).
inline constexpr int kCopies = 32;

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
// The gravity a case's world uses.
Vec3 gravity_of(const Case& c);

struct Reference {
  ref::RefState state;  // body 0 at the end of the case
  std::string name;     // how it was obtained, for the report
};
Reference compute_reference(const Case& c, bool quick);

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

// CPU time of the calling thread (ns): what the cost columns measure.
double thread_cpu_ns();
// The CSV the plot script reads.
void write_csv_header(std::ostream& os);
void write_csv_row(std::ostream& os, const Case& c, const std::string& integrator, double dt,
                   const Row& row, double ns_per_body_step, const std::string& reference);
// Machine, compiler, flags, date: what every figure must carry.
void write_meta(const std::string& path, bool quick, const std::string& extra = "");

}  // namespace rigid::bench
