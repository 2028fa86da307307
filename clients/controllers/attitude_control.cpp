#include "attitude_control.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rigid::controllers {

ThrusterSet::ThrusterSet(const std::array<Thruster, 6>& thrusters, double max_force)
    : thrusters_(thrusters), max_force_(max_force) {
  Eigen::Matrix<double, 6, 6> map;
  for (int i = 0; i < 6; ++i) {
    const Thruster& t = thrusters_[static_cast<std::size_t>(i)];
    map.block<3, 1>(0, i) = t.axis_B;
    map.block<3, 1>(3, i) = t.point_B.cross(t.axis_B);
  }
  const Eigen::FullPivLU<Eigen::Matrix<double, 6, 6>> lu(map);
  if (!lu.isInvertible()) {
    throw std::invalid_argument("thrusters: these six cannot make every force and torque");
  }
  inverse_ = lu.inverse();
}

ThrusterSet ThrusterSet::box(const Vec3& h, double max_force) {
  const Vec3 x = Vec3::UnitX(), y = Vec3::UnitY(), z = Vec3::UnitZ();
  return ThrusterSet({Thruster{h.y() * y, z}, Thruster{-h.y() * y, z},   // torque about x
                      Thruster{h.z() * z, x}, Thruster{-h.z() * z, x},   // about y
                      Thruster{h.x() * x, y}, Thruster{-h.x() * x, y}},  // about z
                     max_force);
}

Thrusts ThrusterSet::allocate(const Vec3& tau_B) const {
  Eigen::Matrix<double, 6, 1> wrench;
  wrench << 0.0, 0.0, 0.0, tau_B;
  const Eigen::Matrix<double, 6, 1> u = inverse_ * wrench;
  const double largest = u.cwiseAbs().maxCoeff();
  const double scale = largest > max_force_ ? max_force_ / largest : 1.0;
  Thrusts out{};
  for (int i = 0; i < 6; ++i)
    out[static_cast<std::size_t>(i)] = scale * u(i);
  return out;
}

double ThrusterSet::max_torque_along(const Vec3& e_B) const {
  Eigen::Matrix<double, 6, 1> wrench;
  wrench << 0.0, 0.0, 0.0, e_B;
  const double largest = (inverse_ * wrench).cwiseAbs().maxCoeff();
  return largest > 0 ? max_force_ / largest : 0.0;
}

Vec3 ThrusterSet::force(const Thrusts& u) const {
  Vec3 f = Vec3::Zero();
  for (std::size_t i = 0; i < 6; ++i)
    f += u[i] * thrusters_[i].axis_B;
  return f;
}

Vec3 ThrusterSet::torque(const Thrusts& u) const {
  Vec3 tau = Vec3::Zero();
  for (std::size_t i = 0; i < 6; ++i)
    tau += thrusters_[i].point_B.cross(u[i] * thrusters_[i].axis_B);
  return tau;
}

AttitudeController::AttitudeController(const Mat3& I_B, ThrusterSet thrusters, const Quat& q_WT,
                                       const AttitudeGains& gains)
    : I_B_(I_B), thrusters_(std::move(thrusters)), q_WT_(q_WT.normalized()), gains_(gains) {}

Vec3 AttitudeController::torque(const Quat& q_WB, const Vec3& w_W) const {
  const Quat q_BW = q_WB.conjugate();
  Quat q_BT = q_BW * q_WT_;                          // body -> target, in the body frame
  if (q_BT.w() < 0) q_BT.coeffs() = -q_BT.coeffs();  // the short way round
  const Vec3 v = q_BT.vec();
  const double s = v.norm();
  const double angle = 2.0 * std::atan2(s, q_BT.w());
  const Vec3 w_B = q_BW * w_W;

  Vec3 w_cmd = Vec3::Zero();
  if (s > 0) {
    const Vec3 e = v / s;
    // What the thrusters can do about e, halved: room to brake from the rate asked for.
    const double alpha = 0.5 * thrusters_.max_torque_along(e) / e.dot(I_B_ * e);
    const double rate =
        std::min({gains_.angle_gain * angle, gains_.max_rate, std::sqrt(alpha * angle)});
    w_cmd = rate * e;
  }
  return I_B_ * (gains_.rate_gain * (w_cmd - w_B)) + w_B.cross(I_B_ * w_B);
}

double angle_between(const Quat& a, const Quat& b) {
  const double d = std::min(1.0, std::abs(a.normalized().dot(b.normalized())));
  return 2.0 * std::acos(d);
}

Mat3 inertia_from(const double* I) {
  Mat3 m;
  m << I[0], I[3], I[4], I[3], I[1], I[5], I[4], I[5], I[2];
  return m;
}

Quat from_rpy(double roll, double pitch, double yaw) {
  return Quat(Eigen::AngleAxisd(yaw, Vec3::UnitZ()) * Eigen::AngleAxisd(pitch, Vec3::UnitY()) *
              Eigen::AngleAxisd(roll, Vec3::UnitX()));
}

}  // namespace rigid::controllers
