// Which peer drivers this build has: CMake defines RIGID_PEER_<ENGINE> for each engine whose
// development package it found, and links only those drivers.
#include "peer_engine.hpp"

namespace rigid::bench::peers {

std::vector<std::unique_ptr<PeerEngine>> built_engines() {
  std::vector<std::unique_ptr<PeerEngine>> engines;
#ifdef RIGID_PEER_MUJOCO
  engines.push_back(make_mujoco_engine());
#endif
#ifdef RIGID_PEER_BULLET
  engines.push_back(make_bullet_engine());
#endif
#ifdef RIGID_PEER_ODE
  engines.push_back(make_ode_engine());
#endif
  return engines;
}

}  // namespace rigid::bench::peers
