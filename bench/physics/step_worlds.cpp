#include "step_worlds.hpp"

namespace rigid::bench {

using physics::BodySpec;
using physics::Frame;
using physics::LoadSpec;
using physics::Vec3;
using physics::WorldSpec;

std::optional<StepCase> find_step_case(std::string_view name) {
  constexpr std::pair<std::string_view, StepCase> kNames[] = {
      {"racket", StepCase::kRacket},
      {"sphere", StepCase::kSphere},
      {"top", StepCase::kTop},
      {"point", StepCase::kPoint},
      {"thruster", StepCase::kThruster},
      {"torqued_top", StepCase::kTorquedTop},
      {"torqued_sphere", StepCase::kTorquedSphere},
      {"lever_top", StepCase::kLeverTop}};
  for (const auto& [n, c] : kNames) {
    if (n == name) return c;
  }
  return std::nullopt;
}

WorldSpec make_step_world(StepCase c, int n, const std::string& integrator) {
  WorldSpec ws;
  ws.dt = 1e-3;
  ws.g_W.setZero();
  ws.integrator = integrator;
  for (int i = 0; i < n; ++i) {
    BodySpec b;
    b.name = "b" + std::to_string(i);
    b.use_gravity = false;
    const double e = 1e-6 * i;
    switch (c) {
      case StepCase::kRacket:
        b.I_B = Vec3(1, 2, 3).asDiagonal();
        b.w_WB = Vec3(1e-3 + e, 5, 1e-3);
        break;
      case StepCase::kSphere:
      case StepCase::kTorquedSphere:
        b.I_B = Vec3(0.4, 0.4, 0.4).asDiagonal();
        b.w_WB = Vec3(1 + e, 2, 3);
        b.v_WBo = Vec3(1, 0, 0);
        if (c == StepCase::kTorquedSphere) {
          ws.loads.push_back(
              LoadSpec{.body = i, .torque = {0, 0.1, 0}, .torque_frame = Frame::kBody});
        }
        break;
      case StepCase::kTop:
      case StepCase::kTorquedTop:
        b.I_B = Vec3(1, 1, 1.8).asDiagonal();
        b.w_WB = Vec3(1 + e, 0, 20);
        if (c == StepCase::kTorquedTop)
          ws.loads.push_back(LoadSpec{.body = i, .torque = {0.1, 0, 0}});
        break;
      case StepCase::kLeverTop:
        b.I_B = Vec3(1, 1, 0.4).asDiagonal();
        b.w_WB = Vec3(0.5 + e, 0.2, 30);
        ws.loads.push_back(LoadSpec{.body = i, .force = {0, 0, -9.81}, .p_BoQ_B = {0, 0, 0.3}});
        break;
      case StepCase::kPoint:
        b.has_inertia = false;
        b.v_WBo = Vec3(1 + e, 2, 3);
        b.use_gravity = true;
        break;
      case StepCase::kThruster:
        b.I_B = Vec3(0.5, 1.0, 1.3).asDiagonal();
        b.w_WB = Vec3(0.2 + e, 0.1, 1.0);
        ws.loads.push_back(LoadSpec{
            .body = i, .force = {0, 0, 4}, .p_BoQ_B = {0.4, 0.1, 0}, .frame = Frame::kBody});
        break;
    }
    ws.bodies.push_back(b);
  }
  return ws;
}

}  // namespace rigid::bench
