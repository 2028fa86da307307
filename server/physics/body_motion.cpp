#include "physics/body_motion.hpp"

namespace rigid::physics {

std::string_view to_string(BodyMotion m) {
  switch (m) {
    case BodyMotion::kTranslation:
      return "translation";
    case BodyMotion::kSteadySpin:
      return "steady_spin";
    case BodyMotion::kPrecession:
      return "precession";
    case BodyMotion::kTumbling:
      return "tumbling";
  }
  return "?";
}

std::string_view to_string(MotionType t) {
  return t == MotionType::kKinematic ? "kinematic" : "dynamic";
}

}  // namespace rigid::physics
