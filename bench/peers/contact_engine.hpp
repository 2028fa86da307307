// The interface every engine's contact driver implements (MuJoCo, Bullet, ODE, and ours), apart
// from the free-body PeerEngine: build a world of copies of a contact case's body over its plane,
// step it, read each copy's state in our frames and what the engine's contact did in the step.
// peer_contacts and the sanity test drive them all through it and score them alike
// (contact_score.hpp).
#pragma once

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "contact_case.hpp"

namespace rigid::bench::peers {

// What an engine's contact between one copy and the plane did over the last step, as the engine
// reports it (README.md says where each engine's figures come from).
struct StepContact {
  int points = 0;             // contact points between the body and the plane
  double normal_impulse = 0;  // the plane's impulse on the body along the normal (N s)
};

// An event an engine located inside a step (ours does; the peers know only step ends).
struct LocatedEvent {
  enum class Kind { kImpact, kResting, kOther };
  Kind kind = Kind::kImpact;
  double time = 0;            // from the start of the run (s)
  double normal_impulse = 0;  // an impact's impulse along the normal (N s)
};

class ContactWorld {
 public:
  virtual ~ContactWorld() = default;
  // Exactly one step of dt for every copy.
  virtual void step() = 0;
  // Copy i's state in our frames (centre of mass, world-frame velocities); all NaN once the engine
  // has diverged (MuJoCo resets a diverged body: that reads as NaN too).
  virtual BodyState state(int i) const = 0;
  // Copy i's contact over the last step; zero unless the world was made with `record`.
  virtual StepContact contact(int i) const = 0;
  // Copy i's events of the last step (empty for engines that do not locate events).
  virtual std::span<const LocatedEvent> events(int) const { return {}; }
};

class ContactEngine {
 public:
  virtual ~ContactEngine() = default;
  // "mujoco", "bullet", "ode", "rigid": the CSV's engine_mode is name() + "_" + mode.
  virtual std::string name() const = 0;
  virtual std::string version() const = 0;
  virtual std::vector<std::string> modes() const = 0;
  // How a mode drives the engine, one line, for the .meta.
  virtual std::string settings(const std::string& mode) const = 0;
  // Whether its worlds locate impacts and rest inside the step (events()): the scorer then takes
  // impact and rest times from the events instead of from the states at step ends.
  virtual bool locates_events() const { return false; }
  // `copies` independent copies of the case's body (copy 0 exactly at the case's start; the others
  // wherever the engine keeps them apart) over the plane if the case has one. `record`: gather
  // contact() (the cost runs do not). Throws std::runtime_error for an unknown mode or a model
  // the engine rejects.
  virtual std::unique_ptr<ContactWorld> make_world(const ContactCase& c, const std::string& mode,
                                                   double dt, int copies, bool record) const = 0;
};

// The peers' contact drivers this build has (those whose packages CMake found).
std::vector<std::unique_ptr<ContactEngine>> built_contact_engines();

std::unique_ptr<ContactEngine> make_mujoco_contact_engine();
std::unique_ptr<ContactEngine> make_bullet_contact_engine();
std::unique_ptr<ContactEngine> make_ode_contact_engine();
// Ours: a physics::World built from the case's WorldSpec (contact_world_spec).
std::unique_ptr<ContactEngine> make_rigid_contact_engine();
physics::WorldSpec contact_world_spec(const ContactCase& c, const std::string& integrator,
                                      double dt, int copies);

}  // namespace rigid::bench::peers
