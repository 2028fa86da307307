// Helpers shared by the physics tests.
#pragma once

#include <algorithm>
#include <cmath>
#include <string>

#include "physics/world.hpp"
#include "reference.hpp"

namespace rigid::test {

using physics::BodySpec;
using physics::Quat;
using physics::Vec3;
using physics::World;
using physics::WorldSpec;

// Angle of the rotation taking a to b (radians, in [0, pi]).
inline double angle_between(const Quat& a, const Quat& b) {
  const double s = (a.conjugate() * b).vec().norm();
  const double c = std::abs((a.conjugate() * b).w());
  return 2.0 * std::atan2(s, c);
}

inline BodySpec body(const std::string& name, const Vec3& I, const Vec3& w0 = Vec3::Zero()) {
  BodySpec b;
  b.name = name;
  b.mass = 1.0;
  b.I_B = I.asDiagonal();
  b.w_WB = w0;
  b.use_gravity = false;
  return b;
}

inline WorldSpec one_body(const BodySpec& b, double dt, const std::string& integrator) {
  WorldSpec ws;
  ws.dt = dt;
  ws.g_W.setZero();
  ws.integrator = integrator;
  ws.bodies.push_back(b);
  return ws;
}

inline Quat to_double(const Q4& q) {
  return Quat(double(q.w()), double(q.x()), double(q.y()), double(q.z())).normalized();
}
inline Vec3 to_double(const V3& v) {
  return Vec3(double(v.x()), double(v.y()), double(v.z()));
}
inline V3 to_ld(const Vec3& v) {
  return V3(v.x(), v.y(), v.z());
}

// The reference state of a torque-free body with principal moments I (B principal) after T.
inline RefState free_reference(const Vec3& I, const Vec3& w0_B, double T, long n) {
  RefBody b;
  b.I = to_ld(I);
  RefState s;
  s.w = to_ld(w0_B);
  ref_run(b, s, T, n);
  return s;
}

}  // namespace rigid::test
