// What the contact stage needs of one body: its state, its motion over part of a step as the
// integrator computes it (with constant contact forces added to its loads), and how it answers
// impulses. The World implements it over its compiled groups; tests implement it in closed form.
#pragma once

#include "physics/contact/point_solver.hpp"
#include "physics/contact/time_of_impact.hpp"
#include "physics/math.hpp"

namespace rigid::physics::contact {

// A constant force through the centre of mass and a torque, both in W, that the supports exert
// on a body over part of a step (the contact forces, solved at its start).
struct SupportLoad {
  Vec3 f_W = Vec3::Zero();
  Vec3 tau_W = Vec3::Zero();
};

class MovingBody {
 public:
  virtual ~MovingBody() = default;
  virtual MotionSample state() const = 0;
  // The body's motion over [0, length] from its state now under its own loads plus `support`: for
  // every s, the state one step of the integrator of size s reaches (the exact flow for a body
  // nothing turns). Valid until the next call on this body.
  virtual const Trajectory& plan(double length, const SupportLoad& support) = 0;
  // Takes the planned motion's state at s.
  virtual void advance(double s) = 0;
  // Sets the velocities (v of the centre of mass, w; in W), as an impulse or a rest does.
  virtual void set_velocity(const Vec3& v_W, const Vec3& w_W) = 0;
  // Moves the body without changing its velocity (a support's drift taken back).
  virtual void shift(const Vec3& d_W) = 0;
  // How the body answers impulses at its current orientation (point_solver.hpp).
  virtual Response response() const = 0;
  // Its acceleration and angular acceleration (W) under its own loads alone, gyroscopic term
  // included: what the supports must act against.
  virtual void free_accelerations(Vec3& a_W, Vec3& alpha_W) const = 0;
  // Kinetic plus potential energy in gravity, the kinetic part alone, and whether its loads are
  // conservative (gravity and nothing else), so that its energy may not rise.
  virtual double energy() const = 0;
  virtual double kinetic_energy() const = 0;
  virtual bool conservative() const = 0;
};

}  // namespace rigid::physics::contact
