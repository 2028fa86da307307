// Bodies touching each other, measured (bench/notes/contact-pairs.md):
//   pairs_bench apart N STEPS   N boxes 3 m apart in zero gravity, drifting and turning, with
//                               shapes (the pair stage on: its broad phase) and without (no
//                               contact stage), alternated 7 times: the medians and their ratio;
//   pairs_bench pile N SECONDS  N spheres poured into a 1 m x 1 m bin (a floor and four walls) at
//                               dt = 1 ms: per simulated second, the wall time per body-step, the
//                               kinetic energy, the deepest any sphere went below the floor and
//                               the farthest out of the walls.
#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

#include "physics/world.hpp"

namespace {

using rigid::physics::BodySpec;
using rigid::physics::PlaneSpec;
using rigid::physics::Shape;
using rigid::physics::ShapeKind;
using rigid::physics::Surface;
using rigid::physics::Vec3;
using rigid::physics::World;
using rigid::physics::WorldSpec;
using Clock = std::chrono::steady_clock;

double apart_ns(int n, bool shaped, int steps) {
  WorldSpec spec;
  spec.dt = 1e-3;
  spec.g_W = Vec3::Zero();
  for (int i = 0; i < n; ++i) {
    BodySpec b;
    b.name = "b" + std::to_string(i);
    b.mass = 1.0;
    const Shape shape{ShapeKind::kBox, Vec3(0.1, 0.2, 0.3)};
    b.I_B = rigid::physics::shape_inertia(shape, 1.0);
    if (shaped) b.shape = shape;
    b.p_WBo = Vec3((i % 10) * 3.0, ((i / 10) % 10) * 3.0, (i / 100) * 3.0);
    b.v_WBo = Vec3(0.01 * ((i * 7) % 5 - 2), 0.01 * ((i * 3) % 5 - 2), 0.0);
    b.w_WB = Vec3(0.3 * (i % 3), 1.0, 0.2);
    spec.bodies.push_back(b);
  }
  World w(spec);
  for (int k = 0; k < 100; ++k)
    w.step();
  const auto t0 = Clock::now();
  for (int k = 0; k < steps; ++k)
    w.step();
  return std::chrono::duration<double>(Clock::now() - t0).count() * 1e9 / steps / n;
}

void pile(int n, double seconds) {
  WorldSpec spec;
  spec.dt = 1e-3;
  spec.g_W = Vec3(0, 0, -9.81);
  const double r = 0.05, half = 0.5;
  const auto wall = [&](const char* name, const Vec3& n_W, double offset) {
    PlaneSpec p;
    p.name = name;
    p.n_W = n_W;
    p.offset = offset;
    spec.planes.push_back(p);
  };
  wall("floor", Vec3(0, 0, 1), 0.0);
  wall("east", Vec3(-1, 0, 0), -half);
  wall("west", Vec3(1, 0, 0), -half);
  wall("north", Vec3(0, -1, 0), -half);
  wall("south", Vec3(0, 1, 0), -half);
  const int per_row = static_cast<int>(2 * half / (2.2 * r));
  unsigned seed = 1;
  for (int i = 0; i < n; ++i) {
    const int ix = i % per_row, iy = (i / per_row) % per_row, iz = i / (per_row * per_row);
    seed = seed * 1103515245u + 12345u;
    const double jitter = ((seed >> 16) % 1000) / 1000.0 * 0.01;
    BodySpec b;
    b.name = "s" + std::to_string(i);
    b.mass = 0.1;
    b.shape = Shape{ShapeKind::kSphere, Vec3(r, 0, 0)};
    b.I_B = rigid::physics::shape_inertia(*b.shape, b.mass);
    b.p_WBo = Vec3(-half + 1.1 * r + ix * 2.2 * r + jitter, -half + 1.1 * r + iy * 2.2 * r,
                   0.2 + iz * 2.2 * r);
    b.surface = Surface{0.3, 0.5};
    spec.bodies.push_back(b);
  }
  World w(spec);
  const int per_second = static_cast<int>(std::lround(1.0 / spec.dt));
  double below = 0.0, out = 0.0;
  for (int s = 1; s <= static_cast<int>(seconds); ++s) {
    const auto t0 = Clock::now();
    for (int k = 0; k < per_second; ++k) {
      w.step();
      for (int i = 0; i < w.body_count(); ++i) {
        const Vec3 p = w.state(i).p_WBo;
        below = std::max(below, r - p.z());
        out = std::max({out, std::abs(p.x()) + r - half, std::abs(p.y()) + r - half});
      }
    }
    const double wall_s = std::chrono::duration<double>(Clock::now() - t0).count();
    double ke = 0.0;
    for (int i = 0; i < w.body_count(); ++i)
      ke += 0.5 * 0.1 * w.state(i).v_WBo.squaredNorm();
    std::printf(
        "t = %d s: %.0f ns per body-step, kinetic energy %.3g J, deepest below the floor "
        "%.3g m, farthest out %.3g m\n",
        s, wall_s * 1e9 / per_second / n, ke, std::max(below, 0.0), std::max(out, 0.0));
  }
}

bool parse(std::string_view text, double& value) {
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  return ec == std::errc() && end == text.data() + text.size() && std::isfinite(value) &&
         value > 0.0;
}

}  // namespace

int main(int argc, char** argv) {
  double n = 0.0, amount = 0.0;
  const std::string_view mode = argc == 4 ? argv[1] : "";
  if ((mode != "apart" && mode != "pile") || !parse(argv[2], n) || n > 1e5 || n != std::floor(n) ||
      !parse(argv[3], amount) || amount > 1e7) {
    std::fprintf(stderr,
                 "usage: pairs_bench apart N STEPS | pairs_bench pile N SECONDS "
                 "(N a whole number 1..100000)\n");
    return 2;
  }
  if (mode == "apart") {
    std::vector<double> bare, shaped;
    for (int k = 0; k < 7; ++k) {
      bare.push_back(apart_ns(static_cast<int>(n), false, static_cast<int>(amount)));
      shaped.push_back(apart_ns(static_cast<int>(n), true, static_cast<int>(amount)));
    }
    std::sort(bare.begin(), bare.end());
    std::sort(shaped.begin(), shaped.end());
    std::printf(
        "%d bodies apart: without shapes %.2f ns per body-step, with shapes (pair stage) "
        "%.2f, ratio %.3f (medians of 7, alternated)\n",
        static_cast<int>(n), bare[3], shaped[3], shaped[3] / bare[3]);
  } else {
    pile(static_cast<int>(n), amount);
  }
  return 0;
}
