#include "model_worlds.hpp"

#include <malloc.h>
#include <unistd.h>

#include <fstream>
#include <string>
#include <utility>

namespace rigid::bench {

using physics::BodySpec;
using physics::Frame;
using physics::LoadSpec;
using physics::Vec3;
using physics::WorldSpec;

namespace {

constexpr ModelInfo kModels[] = {
    {Model::kPoint, "point", "point mass under gravity"},
    {Model::kIsotropic, "isotropic", "I = 0.4 (1, 1, 1), w0 = (1, 2, 3), moving"},
    {Model::kAxisymmetric, "axisymmetric", "I = (1, 1, 1.8), w0 = (1, 0, 20)"},
    {Model::kGeneral, "general", "racket: I = (1, 2, 3), w0 = (1e-3, 5, 1e-3)"},
    {Model::kGeneralForced, "general_forced",
     "thruster: I = (0.5, 1, 1.3), m = 2, f_B = (0, 0, 4) at (0.4, 0.1, 0)"},
};

}  // namespace

std::span<const ModelInfo> all_models() {
  return kModels;
}

std::optional<Model> find_model(std::string_view name) {
  for (const ModelInfo& m : kModels)
    if (name == m.name) return m.model;
  return std::nullopt;
}

WorldSpec make_model_world(Model model, int n) {
  WorldSpec ws;
  ws.dt = 1e-3;
  ws.g_W.setZero();
  ws.bodies.reserve(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    BodySpec b;
    b.name = "b" + std::to_string(i);
    b.use_gravity = false;
    const double e = 1e-6 * (i % 1000);
    switch (model) {
      case Model::kPoint:
        b.has_inertia = false;
        b.v_WBo = Vec3(1 + e, 2, 3);
        b.use_gravity = true;
        break;
      case Model::kIsotropic:
        b.I_B = Vec3(0.4, 0.4, 0.4).asDiagonal();
        b.w_WB = Vec3(1 + e, 2, 3);
        b.v_WBo = Vec3(1, 0, 0);
        break;
      case Model::kAxisymmetric:
        b.I_B = Vec3(1, 1, 1.8).asDiagonal();
        b.w_WB = Vec3(1 + e, 0, 20);
        break;
      case Model::kGeneral:
        b.I_B = Vec3(1, 2, 3).asDiagonal();
        b.w_WB = Vec3(1e-3 + e, 5, 1e-3);
        break;
      case Model::kGeneralForced:
        b.mass = 2;
        b.I_B = Vec3(0.5, 1.0, 1.3).asDiagonal();
        b.w_WB = Vec3(0.2 + e, 0.1, 1.0);
        ws.loads.push_back(LoadSpec{
            .body = i, .force = {0, 0, 4}, .p_BoQ_B = {0.4, 0.1, 0}, .frame = Frame::kBody});
        break;
    }
    ws.bodies.push_back(std::move(b));
  }
  if (model == Model::kPoint) ws.g_W = Vec3(0, 0, -9.81);
  return ws;
}

double heap_bytes() {
  const struct mallinfo2 m = mallinfo2();
  return static_cast<double>(m.uordblks + m.hblkhd);
}

double rss_bytes() {
  std::ifstream statm("/proc/self/statm");
  double size = 0, resident = 0;
  statm >> size >> resident;
  return resident * static_cast<double>(sysconf(_SC_PAGESIZE));
}

}  // namespace rigid::bench
