#include "peer_body.hpp"

#include <stdexcept>

namespace rigid::bench::peers {

Vec3 principal_moments(const Case& c) {
  const BodySpec& b = c.body;
  const bool frozen = b.freeze_translation[0] || b.freeze_translation[1] ||
                      b.freeze_translation[2] || b.freeze_rotation[0] || b.freeze_rotation[1] ||
                      b.freeze_rotation[2];
  if (b.kinematic || !b.has_inertia || frozen) {
    throw std::runtime_error("case '" + c.name +
                             "': peers are only given free dynamic bodies with inertia");
  }
  const physics::Mat3 off = b.I_B - physics::Mat3(b.I_B.diagonal().asDiagonal());
  if (off.cwiseAbs().maxCoeff() != 0.0) {
    throw std::runtime_error("case '" + c.name + "': the body frame must be principal");
  }
  for (const LoadSpec& l : c.loads) {
    if (l.body != 0) throw std::runtime_error("case '" + c.name + "': loads must be on body 0");
  }
  return b.I_B.diagonal();
}

bool has_body_frame_load(const Case& c) {
  for (const LoadSpec& l : c.loads) {
    if ((l.frame == Frame::kBody && !l.force.isZero()) ||
        (l.torque_frame == Frame::kBody && !l.torque.isZero())) {
      return true;
    }
  }
  return false;
}

bool has_drag(const Case& c) {
  return c.body.linear_drag > 0 || c.body.angular_drag > 0;
}

}  // namespace rigid::bench::peers
