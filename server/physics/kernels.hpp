// The integrators' step kernels, one file each (integrate_*.cpp). Each advances its share of every
// group (Share: the bodies one thread steps) by one step of the model's dt, evaluating loads at
// every stage it needs them. Every kernel reads the Model const and writes the Data.
#pragma once

#include <cmath>
#include <cstdint>

#include "physics/data.hpp"
#include "physics/integrator.hpp"
#include "physics/model.hpp"

namespace rigid::physics::detail {

// A run of entries of one group, [begin, end).
struct Range {
  int begin = 0, end = 0;
};

// One chunk of a step's work, which one thread claims and does (pool.hpp): per group (by
// index(kind)), a contiguous slice of all its entries (for integrators with one path), and a slice
// of each run (quiet, loaded) for those with a path per kind. The slices of all chunks cover each
// group exactly once; a body's arithmetic never depends on which thread or slice steps it, so
// states are bit-identical for any number of threads.
struct Share {
  Range all[kBodyMotions];
  Range run[kBodyMotions][2];  // [group][0: quiet, 1: loaded]
  // Body-steps of this share in which a body turned by more than pi (see Data::large_rotations).
  std::int64_t large_rotations = 0;
  // Caches made by fill_quiet_caches in this share.
  std::int64_t caches_made = 0;

  // Counts a step of angle |w| dt > pi.
  void note_rotation(double dt, const Vec3& w) {
    constexpr double kPi2 = 9.8696044010893586188;  // pi^2
    if (dt * dt * w.squaredNorm() > kPi2) ++large_rotations;
  }
};

// The course notes' schemes (GAMES103, "Rigid Body Dynamics"): explicit Euler, semi-implicit
// Euler, midpoint or leapfrog for translation, each with the notes' rotation update.
void step_notes(const Model& m, Data& d, IntegratorId which, Share& sh);
// Catto's implicit gyroscopic step (GDC 2015 "Numerical Methods").
void step_implicit_gyro(const Model& m, Data& d, Share& sh);
// Classical Runge-Kutta 4 on the full state (x, v, q, w).
void step_rk4(const Model& m, Data& d, Share& sh);
// Kick-drift-kick with the Dullweber-Leimkuhler-McLachlan free-rotor splitting.
void step_dlm(const Model& m, Data& d, Share& sh);
// Kick-drift-kick with the exact free rotor; fourth_order: Suzuki's composition of it.
void step_exact(const Model& m, Data& d, bool fourth_order, Share& sh);
// hybrid4: quiet bodies take one exact free-rotor step, loaded ones a fourth-order composition
// whose drifts are cheap (integrate_exact.cpp).
void step_hybrid(const Model& m, Data& d, Share& sh, int variant);
// For the integrators whose quiet run caches its exact drift (exact_rotor, exact_rotor4, hybrid4):
// makes the stale caches of the share's quiet entries, as their next step would, and counts them
// in sh.caches_made (World::prepare_step).
void fill_quiet_caches(const Model& m, Data& d, Share& sh);

// The kick of the spin (w_P or h_P, see groups.hpp) over s: spin' = rate - decay . spin with the
// torque's rate constant, solved exactly per principal axis (angular drag as an exact decay):
// spin_i <- e^{-d_i s} spin_i + s phi1(-d_i s) rate_i. With no drag: spin += s rate.
inline void kick_angular(const Vec3& rate, const Vec3& decay, double s, Vec3& spin) {
  for (int i = 0; i < 3; ++i) {
    if (decay[i] == 0.0) {
      spin[i] += s * rate[i];
    } else {
      const double z = -decay[i] * s;
      const double em1 = std::expm1(z);
      spin[i] = (1.0 + em1) * spin[i] + s * (em1 / z) * rate[i];
    }
  }
}

// The translation parameters of consecutive entries of a group and their coefficients for one
// step size, fetched again only when an entry's row differs from the last one's. Bodies mostly
// share a few rows, so the quiet loops load a 4 B index a body instead of following it to the
// shared row and on to its drag row each time.
class LinearCursor {
 public:
  template <class G>
  LinearCursor(const G& g, const Model& m, TransSize size)
      : rows_(g.entries.linear.data()), table_(g.params.linear.data()), m_(m), size_(size) {}
  void at(int i) {
    const int k = rows_[i];
    if (k == k_) return;
    k_ = k;
    lin_ = table_[k];
    tc_ = m_.tc(lin_, size_);
  }
  const Linear& lin() const { return lin_; }
  const TransCoef& tc() const { return tc_; }

 private:
  const std::int32_t* rows_;
  const Linear* table_;
  const Model& m_;
  TransSize size_;
  int k_ = -1;
  Linear lin_;
  TransCoef tc_;
};

// The halves of the lanes kernels that know the groups (hybrid_lanes.hpp, rotor_lanes.hpp say
// what the kernels do; their own headers stay free of the model's types).
//
// Steps the entries [r.begin, r.end) of the group's loaded run by one hybrid4 step of m.dt, with
// the kernel m.lanes names (hybrid_lanes.cpp).
void hybrid_loaded_lanes(TumblingGroup g, const Model& m, Range r);
void hybrid_loaded_lanes(PrecessionGroup g, const Model& m, Range r);
// Whether the eight entries of block k (8k .. 8k + 7, all of which exist) have cached plans that
// are valid and can step in the kernel (made, not still, short steps with nodes) (rotor_lanes.cpp).
bool rotor_block_ready(const TumblingGroup& g, int block);
// Block k of g (entries 8k .. 8k + 7) into the state lanes, and back.
void rotor_gather_block(const TumblingGroup& g, int block, RotorStateLanes& st);
void rotor_scatter_block(const RotorStateLanes& st, int block, const TumblingGroup& g);

}  // namespace rigid::physics::detail
