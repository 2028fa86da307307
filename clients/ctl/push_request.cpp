#include "ctl/push_request.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace rigid::ctl {
namespace {

double norm(const rigid::Vec3& v) {
  return std::hypot(v[0], v[1], v[2]);
}

rigid::Vec3 cross(const rigid::Vec3& a, const rigid::Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

std::string num(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.4g", v);
  return buffer;
}

}  // namespace

PushRequest make_push(const CtlOptions& o, const rigid::SceneDescription& scene,
                      std::int32_t body) {
  PushRequest p;
  rigid::WrenchCommand& w = p.wrench;
  w.body_id = body;
  w.body_name = scene.names[static_cast<std::size_t>(body)];
  w.force = o.force;
  w.point = o.point;
  w.force_frame = o.frame;
  w.torque = o.torque;
  w.torque_frame = o.frame;
  w.ttl = o.for_seconds.value_or(scene.max_ttl > 0 ? std::min(kDefaultPushSeconds, scene.max_ttl)
                                                   : kDefaultPushSeconds);
  // The checks of rigidd's command validation (loop/command_validation.cpp), in its order; a limit
  // <= 0 is none.
  const double force = norm(w.force);
  const double torque = norm(w.torque);
  const double moment = norm(cross(w.point, w.force));
  if (scene.max_force > 0 && force > scene.max_force) {
    p.refusal = "--force: |f| = " + num(force) + " N is above the scene's max_force of " +
                num(scene.max_force) + " N";
  } else if (scene.max_torque > 0 && torque > scene.max_torque) {
    p.refusal = "--torque: |t| = " + num(torque) + " N m is above the scene's max_torque of " +
                num(scene.max_torque) + " N m";
  } else if (scene.max_torque > 0 && moment > scene.max_torque) {
    p.refusal = "--at: |point x force| = " + num(moment) +
                " N m is above the scene's max_torque of " + num(scene.max_torque) + " N m";
  } else if (scene.max_ttl > 0 && w.ttl > scene.max_ttl) {
    p.refusal =
        "--for " + num(w.ttl) + " s is above the scene's max_ttl of " + num(scene.max_ttl) + " s";
  }
  return p;
}

std::string push_summary(const PushRequest& push, const CtlOptions& o,
                         const rigid::SceneDescription& scene) {
  const rigid::WrenchCommand& w = push.wrench;
  // A wrench acts for its ttl, and at least the tick it takes effect in (ttl 0).
  const double seconds = std::max(w.ttl, scene.dt);
  std::string text;
  if (w.ttl > 0) {
    text = "for " + num(w.ttl) + " s";
    if (!o.for_seconds) text += " (default; --for S)";
  } else {
    text = "for one tick (" + num(scene.dt * 1e3) + " ms; --for S pushes longer)";
  }
  std::vector<std::string> parts;
  const double force = norm(w.force);
  if (force > 0) {
    std::string part = "impulse " + num(force * seconds) + " N s";
    const double mass = scene.masses[static_cast<std::size_t>(w.body_id)];
    if (mass > 0)
      part += ", |dv| " + num(force * seconds / mass) + " m/s on its " + num(mass) + " kg";
    parts.push_back(part);
  }
  const double torque = norm(w.torque);
  if (torque > 0) parts.push_back("angular impulse " + num(torque * seconds) + " N m s");
  for (std::size_t i = 0; i < parts.size(); ++i)
    text += (i == 0 ? ": " : "; ") + parts[i];
  return text;
}

}  // namespace rigid::ctl
