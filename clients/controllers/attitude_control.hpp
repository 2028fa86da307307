// The mathematics of rigid-attitude, with no bus: six body-fixed thrusters and an attitude law that
// turns a body to a target orientation and holds it there.
//
// Thrusters: each pushes along a fixed body axis at a fixed body point, with a signed thrust
// |u| <= max_force (a reversible thruster, or a back-to-back pair). The box layout puts them in
// three couples on the box's faces, so they can make any body torque with no net force: the 6x6
// map from thrusts to (force, torque) is inverted once, and a demand beyond what they can give is
// scaled down as a whole, keeping the torque's direction.
//
// Law (cascaded, so that the thrust bound cannot wind it up): the rotation from the body to the
// target, phi (axis times angle, body frame, the short way round), asks for a turn rate along phi
// of min(angle_gain * angle, max_rate, sqrt(alpha * angle)), where alpha is the angular
// acceleration the thrusters give about that axis, halved: a rate the body can still brake from
// in the angle left. The body torque then drives the body rate to it, with the gyroscopic term
// cancelled: tau = I rate_gain (w_cmd - w) + w x I w.
#pragma once

#include <Eigen/Dense>
#include <array>

namespace rigid::controllers {

// Eigen's own types: the controller needs quaternion and rotation algebra, not the physics core.
using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Quat = Eigen::Quaterniond;

struct Thruster {
  Vec3 point_B;  // from the centre of mass, body frame (m)
  Vec3 axis_B;   // unit; the force is u * axis_B
};

using Thrusts = std::array<double, 6>;

class ThrusterSet {
 public:
  // Throws std::invalid_argument if the six cannot make every wrench (their map is singular).
  ThrusterSet(const std::array<Thruster, 6>& thrusters, double max_force);

  // Three couples on the faces of a box of these half extents (body frame): two on the +-y faces
  // pushing along z (torque about x), two on the +-z faces along x (about y), two on the +-x faces
  // along y (about z).
  static ThrusterSet box(const Vec3& half_extents, double max_force);

  // Thrusts for the body torque tau_B with no net force, scaled down together if any would exceed
  // max_force.
  Thrusts allocate(const Vec3& tau_B) const;
  // The largest torque along the unit axis e_B the thrusters can give (no net force).
  double max_torque_along(const Vec3& e_B) const;
  // The body-frame force and torque that thrusts `u` make.
  Vec3 force(const Thrusts& u) const;
  Vec3 torque(const Thrusts& u) const;

  const std::array<Thruster, 6>& thrusters() const { return thrusters_; }
  double max_force() const { return max_force_; }

 private:
  std::array<Thruster, 6> thrusters_;
  double max_force_;
  Eigen::Matrix<double, 6, 6> inverse_;  // (force; torque) -> thrusts
};

struct AttitudeGains {
  double angle_gain = 1.5;  // 1/s: turn rate asked per radian of error
  double rate_gain = 8.0;   // 1/s: how fast the body rate follows
  double max_rate = 1.5;    // rad/s
};

class AttitudeController {
 public:
  AttitudeController(const Mat3& I_B, ThrusterSet thrusters, const Quat& q_WT,
                     const AttitudeGains& gains = {});

  // The body torque for the state q_WB (body to world), w_W (world frame).
  Vec3 torque(const Quat& q_WB, const Vec3& w_W) const;
  Thrusts thrusts(const Quat& q_WB, const Vec3& w_W) const {
    return thrusters_.allocate(torque(q_WB, w_W));
  }
  const ThrusterSet& thrusters() const { return thrusters_; }
  const Quat& target() const { return q_WT_; }

 private:
  Mat3 I_B_;
  ThrusterSet thrusters_;
  Quat q_WT_;
  AttitudeGains gains_;
};

// The angle of the rotation between two orientations (rad, in [0, pi]).
double angle_between(const Quat& a, const Quat& b);

// The body-frame inertia tensor from SceneInfo's six numbers (Ixx, Iyy, Izz, Ixy, Ixz, Iyz).
Mat3 inertia_from(const double* six);

// A quaternion from roll, pitch, yaw (rad; rotations about x, then y, then z, of the world).
Quat from_rpy(double roll, double pitch, double yaw);

}  // namespace rigid::controllers
