// The interface every peer engine's driver (MuJoCo, Bullet, ODE) implements, so that
// peer_work_precision and the sanity test drive them all through the same code as
// bench/work_precision drives ours: build a world of copies of a hard case's body, step it, read
// body states back in our frames, and score them with bench/physics/hard_cases' Scorer.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "hard_cases.hpp"

namespace rigid::bench::peers {

// One peer world: `copies` identical, independent copies of a case's body, in one mode of the
// peer, stepped with a fixed dt.
class PeerWorld {
 public:
  virtual ~PeerWorld() = default;
  // Exactly one step of dt for every copy, the case's loads (forces at points, drag) applied the
  // way this peer requires them.
  virtual void step() = 0;
  // Copy i's state in our frames (centre of mass, world-frame velocities). All NaN once the peer
  // has diverged, including where the peer itself hides it (MuJoCo resets a diverged body to its
  // start pose), so that the Scorer reports the run as blown up.
  virtual BodyState state(int i) const = 0;
};

class PeerEngine {
 public:
  virtual ~PeerEngine() = default;
  // "mujoco", "bullet", "ode": the CSV's integrator column is name() + "_" + mode.
  virtual std::string name() const = 0;
  // Library version and precision, for the metadata file.
  virtual std::string version() const = 0;
  // The modes that apply to a case (some only exist for body-frame forces or for drag).
  virtual std::vector<std::string> modes(const Case& c) const = 0;
  // Throws std::runtime_error when the mode is unknown or the peer rejects the model.
  virtual std::unique_ptr<PeerWorld> make_world(const Case& c, const std::string& mode, double dt,
                                                int copies) const = 0;
};

// The engines this build has: those whose development packages CMake found.
std::vector<std::unique_ptr<PeerEngine>> built_engines();

std::unique_ptr<PeerEngine> make_mujoco_engine();
std::unique_ptr<PeerEngine> make_bullet_engine();
std::unique_ptr<PeerEngine> make_ode_engine();
// Ours through the same interface ("rigid", one mode per integrator), to be timed in the same run.
std::unique_ptr<PeerEngine> make_rigid_engine();

}  // namespace rigid::bench::peers
