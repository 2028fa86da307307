// The integrators' step kernels, one file each (integrate_*.cpp). Each advances its share of every
// group of the model (Share: the bodies one thread steps) by one step of model.dt, evaluating loads
// at every stage it needs them.
#pragma once

#include "physics/integrator.hpp"
#include "physics/model.hpp"

namespace rigid::physics::detail {

// The course notes' schemes (GAMES103, "Rigid Body Dynamics"): explicit Euler, semi-implicit
// Euler, midpoint or leapfrog for translation, each with the notes' rotation update.
void step_notes(Model& m, IntegratorId which, Share& sh);
// Catto's implicit gyroscopic step (GDC 2015 "Numerical Methods").
void step_implicit_gyro(Model& m, Share& sh);
// Classical Runge-Kutta 4 on the full state (x, v, q, w).
void step_rk4(Model& m, Share& sh);
// Kick-drift-kick with the Dullweber-Leimkuhler-McLachlan free-rotor splitting.
void step_dlm(Model& m, Share& sh);
// Kick-drift-kick with the exact free rotor; fourth_order: Suzuki's composition of it.
void step_exact(Model& m, bool fourth_order, Share& sh);
// hybrid4: quiet bodies take one exact free-rotor step, loaded ones a fourth-order composition
// whose drifts are cheap (integrate_exact.cpp).
void step_hybrid(Model& m, Share& sh, int variant);
// For the integrators whose quiet run caches its exact drift (exact_rotor, exact_rotor4, hybrid4):
// makes the stale caches of the share's quiet entries, as their next step would, and counts them
// in sh.caches_made (World::prepare_step).
void fill_quiet_caches(Model& m, Share& sh);

// The kick of the spin (w_P or h_P, see model.hpp) over s: spin' = rate - decay . spin with the
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

}  // namespace rigid::physics::detail
