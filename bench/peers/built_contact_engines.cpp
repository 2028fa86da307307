// Which peers' contact drivers this build has: CMake defines RIGID_CONTACT_<ENGINE> for each engine
// whose development package it found, and links only those drivers.
#include "contact_engine.hpp"

namespace rigid::bench::peers {

std::vector<std::unique_ptr<ContactEngine>> built_contact_engines() {
  std::vector<std::unique_ptr<ContactEngine>> engines;
#ifdef RIGID_CONTACT_MUJOCO
  engines.push_back(make_mujoco_contact_engine());
#endif
#ifdef RIGID_CONTACT_BULLET
  engines.push_back(make_bullet_contact_engine());
#endif
#ifdef RIGID_CONTACT_ODE
  engines.push_back(make_ode_contact_engine());
#endif
  return engines;
}

}  // namespace rigid::bench::peers
