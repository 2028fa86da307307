// libFuzzer target: scene text (server/scene). Any text must give a Scene or a SceneError, nothing
// else: another exception escaping is a crash here, as are sanitizer findings. A refusal must be
// the promised one line, "NAME:LINE:COL: message" (or "NAME: message"), printable. A scene that
// loads must hold what scene.hpp promises and give a world the physics builds and steps.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "fuzz_require.hpp"
#include "physics/world.hpp"
#include "scene/scene.hpp"

namespace {

using rigid::fuzz::require;

constexpr std::string_view kName = "fuzz.pbtxt";

// Errors and warnings are printed one per line: printable ASCII only (a byte from the file, such
// as a line break or a terminal escape, is shown as \xHH).
bool one_line_about_the_file(const std::string& s) {
  return s.starts_with(kName) && std::all_of(s.begin(), s.end(), [](char c) {
           const auto u = static_cast<unsigned char>(c);
           return u >= 0x20 && u < 0x7f;
         });
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  rigid::scene::Scene scene;
  try {
    scene = rigid::scene::parse_scene(text, kName);
  } catch (const rigid::scene::SceneError& e) {
    require(one_line_about_the_file(e.what()), "a scene error is one line naming the file");
    require(e.line() >= 0, "a scene error's line is 0 (none) or a line");
    return 0;
  }

  require(scene.shapes.size() == scene.world.bodies.size(), "one shape entry per body");
  require(scene.rate_hz > 0.0 && scene.rate_hz <= 1e6, "0 < rate_hz <= 1e6");
  require(scene.substeps >= 1 && scene.substeps <= 10000, "1 <= substeps <= 10000");
  require(scene.publish_every >= 1, "publish_every >= 1");
  require(std::isfinite(scene.world.dt) && scene.world.dt > 0.0, "dt is finite and positive");
  require(
      scene.limits.max_force > 0.0 && scene.limits.max_torque > 0.0 && scene.limits.max_ttl > 0.0,
      "limits are positive");
  // Static parts and materials (contacts): every surface within its bounds, planes with unit
  // normals, part names unique and none a body's.
  const auto surface_ok = [](const rigid::physics::Surface& s) {
    return s.restitution >= 0.0 && s.restitution <= 1.0 && s.friction >= 0.0 &&
           std::isfinite(s.friction);
  };
  std::vector<std::string> names;
  for (const rigid::physics::BodySpec& b : scene.world.bodies) {
    require(surface_ok(b.surface), "a body's material is in bounds");
    names.push_back(b.name);
  }
  for (const rigid::physics::PlaneSpec& p : scene.world.planes) {
    require(surface_ok(p.surface), "a plane's material is in bounds");
    require(std::abs(p.n_W.norm() - 1.0) < 1e-12 && std::isfinite(p.offset),
            "a plane's normal is a unit vector and its offset finite");
    names.push_back(p.name);
  }
  for (const rigid::physics::StaticSpec& s : scene.world.statics) {
    require(surface_ok(s.surface), "a static shape's material is in bounds");
    require(s.shape.kind != rigid::physics::ShapeKind::kEllipsoid,
            "a static shape is a box, sphere, capsule or cylinder");
    names.push_back(s.name);
  }
  std::sort(names.begin(), names.end());
  require(std::adjacent_find(names.begin(), names.end()) == names.end(),
          "names are unique among bodies and static parts");
  for (const std::string& w : scene.warnings) {
    require(one_line_about_the_file(w), "a warning is one line naming the file");
  }
  // parse_scene has already built it once; a SpecError escaping here would be a scene it accepted
  // that the physics refuses. Two steps exercise every body model and load the scene compiled to.
  rigid::physics::World world(scene.world);
  world.step(2);
  return 0;
}
