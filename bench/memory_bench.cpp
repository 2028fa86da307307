// Memory a World takes per body, for a world of N bodies (default 10^6) of one model: the resident
// set's growth (/proc/self/statm) over the World's construction and its first steps (pages
// actually touched), and glibc's count of heap bytes in use (mallinfo2), both per body. The
// WorldSpec is built before the first reading and kept alive, so neither counts it. Each model
// runs in its own child process, so that memory freed by one is not reused by the next.
//
//   build/bench/memory_bench [--bodies 1000000] [--models general,isotropic,...]
//
// Output: one line per model, "RESULT memory <model> rss_bytes_per_body X heap_bytes_per_body Y".
#include <malloc.h>
#include <sys/wait.h>
#include <unistd.h>

#include <charconv>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "physics/world.hpp"

namespace {

using rigid::physics::BodySpec;
using rigid::physics::Frame;
using rigid::physics::LoadSpec;
using rigid::physics::Vec3;
using rigid::physics::World;
using rigid::physics::WorldSpec;

// The bodies of throughput.cpp's models: torque-free general (racket), spheres, symmetric tops,
// point masses, and the general body pushed by a body-fixed force off its centre (thruster).
const char* const kModels[] = {"general", "isotropic", "axisymmetric", "point", "general_forced"};

WorldSpec make_spec(const std::string& model, int n) {
  WorldSpec ws;
  ws.dt = 1e-3;
  ws.g_W.setZero();
  ws.bodies.reserve(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    BodySpec b;
    b.name = "body_" + std::to_string(i);
    b.use_gravity = false;
    const double e = 1e-6 * (i % 1000);
    if (model == "point") {
      b.has_inertia = false;
      b.v_WBo = Vec3(1 + e, 2, 3);
      b.use_gravity = true;
    } else if (model == "isotropic") {
      b.I_B = Vec3(0.4, 0.4, 0.4).asDiagonal();
      b.w_WB = Vec3(1 + e, 2, 3);
      b.v_WBo = Vec3(1, 0, 0);
    } else if (model == "axisymmetric") {
      b.I_B = Vec3(1, 1, 1.8).asDiagonal();
      b.w_WB = Vec3(1 + e, 0, 20);
    } else if (model == "general") {
      b.I_B = Vec3(1, 2, 3).asDiagonal();
      b.w_WB = Vec3(1e-3 + e, 5, 1e-3);
    } else {  // general_forced
      b.mass = 2;
      b.I_B = Vec3(0.5, 1.0, 1.3).asDiagonal();
      b.w_WB = Vec3(0.2 + e, 0.1, 1.0);
      ws.loads.push_back(
          LoadSpec{.body = i, .force = {0, 0, 4}, .p_BoQ_B = {0.4, 0.1, 0}, .frame = Frame::kBody});
    }
    ws.bodies.push_back(std::move(b));
  }
  if (model == "point") ws.g_W = Vec3(0, 0, -9.81);
  return ws;
}

double rss_bytes() {
  std::ifstream statm("/proc/self/statm");
  double size = 0, resident = 0;
  statm >> size >> resident;
  return resident * static_cast<double>(sysconf(_SC_PAGESIZE));
}

double heap_bytes() {
  const struct mallinfo2 m = mallinfo2();
  return static_cast<double>(m.uordblks + m.hblkhd);
}

int measure(const std::string& model, int n) {
  const WorldSpec spec = make_spec(model, n);
  const double rss0 = rss_bytes(), heap0 = heap_bytes();
  World w(spec);
  const double heap = heap_bytes() - heap0;
  // Steps touch the caches built lazily (rotor plans) and, at the 64th, the guard's copies.
  w.step(World::kGuardEvery);
  const double rss = rss_bytes() - rss0;
  std::printf("RESULT memory %s rss_bytes_per_body %.1f heap_bytes_per_body %.1f bodies %d\n",
              model.c_str(), rss / n, heap / n, n);
  std::fflush(stdout);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  int bodies = 1'000'000;
  std::vector<std::string> models(std::begin(kModels), std::end(kModels));
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--bodies" && i + 1 < argc) {
      const std::string v = argv[++i];
      const auto [end, ec] = std::from_chars(v.data(), v.data() + v.size(), bodies);
      if (ec != std::errc() || end != v.data() + v.size() || bodies < 1 || bodies > 20'000'000) {
        std::cerr << "memory_bench: --bodies: expected 1 .. 20000000, got '" << v << "'\n";
        return 2;
      }
    } else if (a == "--models" && i + 1 < argc) {
      models.clear();
      std::stringstream ss(argv[++i]);
      for (std::string m; std::getline(ss, m, ',');) {
        bool known = false;
        for (const char* k : kModels)
          known = known || m == k;
        if (!known) {
          std::cerr << "memory_bench: --models: unknown model '" << m << "'\n";
          return 2;
        }
        models.push_back(m);
      }
    } else {
      std::cerr << "usage: memory_bench [--bodies N] [--models general,isotropic,axisymmetric,"
                   "point,general_forced]\n";
      return a == "--help" || a == "-h" ? 0 : 2;
    }
  }
  for (const std::string& m : models) {
    const pid_t child = fork();
    if (child < 0) {
      std::perror("memory_bench: fork");
      return 1;
    }
    if (child == 0) _exit(measure(m, bodies));
    int status = 0;
    if (waitpid(child, &status, 0) != child || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
      std::cerr << "memory_bench: the run for '" << m << "' failed\n";
      return 1;
    }
  }
  return 0;
}
