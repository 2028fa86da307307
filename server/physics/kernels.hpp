// The integrators' step kernels, one file each (integrate_*.cpp). Each advances every group of the
// model by one step of model.dt, evaluating loads at every stage it needs them.
#pragma once

#include "physics/integrator.hpp"
#include "physics/model.hpp"

namespace rigid::physics::detail {

// The course notes' schemes (GAMES103, "Rigid Body Dynamics"): explicit Euler, semi-implicit
// Euler, midpoint or leapfrog for translation, each with the notes' rotation update.
void step_notes(Model& m, IntegratorId which);
// Catto's implicit gyroscopic step (GDC 2015 "Numerical Methods").
void step_implicit_gyro(Model& m);
// Classical Runge-Kutta 4 on the full state (x, v, q, w).
void step_rk4(Model& m);
// Kick-drift-kick with the Dullweber-Leimkuhler-McLachlan free-rotor splitting.
void step_dlm(Model& m);
// Kick-drift-kick with the exact free rotor; fourth_order: Suzuki's composition of it.
void step_exact(Model& m, bool fourth_order);

// Exact decay of w under angular drag over s with constant torque, per principal axis:
// w_i <- e^{-r_i s} w_i + s phi1(-r_i s) alpha_i, r_i = k / I_i. With k == 0: w += s alpha.
inline void kick_angular(const Vec3& alpha, const Vec3& rate, double s, Vec3& w) {
  for (int i = 0; i < 3; ++i) {
    if (rate[i] == 0.0) {
      w[i] += s * alpha[i];
    } else {
      const double z = -rate[i] * s;
      const double em1 = std::expm1(z);
      w[i] = (1.0 + em1) * w[i] + s * (em1 / z) * alpha[i];
    }
  }
}

}  // namespace rigid::physics::detail
