// Memory a World takes per body, for a world of N bodies (default 10^6) of one model: the resident
// set's growth (/proc/self/statm) over the World's construction and its first steps (pages
// actually touched), and glibc's count of heap bytes in use (mallinfo2), both per body. The
// WorldSpec is built before the first reading and kept alive, so neither counts it. Each model
// runs in its own child process, so that memory freed by one is not reused by the next.
//
//   build/bench/memory_bench [--bodies 1000000] [--models general,isotropic,...] [--distinct]
//
// The worlds are bench/physics/model_worlds.cpp's: bodies of one kind, at the origin, whose initial spins
// take 1000 values. --distinct gives each body its own position and initial velocities, so that
// nothing of its initial state can be shared (World keeps an initial orientation and velocities
// once per distinct value): the worst case.
//
// Output: one line per model, "RESULT memory <model> rss_bytes_per_body X heap_bytes_per_body Y".
#include <sys/wait.h>
#include <unistd.h>

#include <charconv>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "model_worlds.hpp"
#include "physics/world.hpp"

namespace {

using rigid::bench::heap_bytes;
using rigid::bench::rss_bytes;
using rigid::physics::World;
using rigid::physics::WorldSpec;

int measure(const std::string& model, int n, bool distinct) {
  WorldSpec spec = rigid::bench::make_model_world(*rigid::bench::find_model(model), n);
  if (distinct) {
    for (int i = 0; i < n; ++i) {
      auto& b = spec.bodies[static_cast<std::size_t>(i)];
      b.p_WBo = rigid::physics::Vec3(i, 0, 0);
      b.v_WBo.y() += 1e-9 * i;
      b.w_WB.y() += 1e-9 * i;
    }
  }
  const double rss0 = rss_bytes(), heap0 = heap_bytes();
  World w(spec);
  const double heap = heap_bytes() - heap0;
  // Steps touch the caches built lazily (rotor plans) and, a slice a step, the guard's copies.
  w.step(World::kGuardEvery);
  const double rss = rss_bytes() - rss0;
  std::printf("RESULT memory %s%s rss_bytes_per_body %.1f heap_bytes_per_body %.1f bodies %d\n",
              model.c_str(), distinct ? "_distinct" : "", rss / n, heap / n, n);
  std::fflush(stdout);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  int bodies = 1'000'000;
  bool distinct = false;
  std::vector<std::string> models;
  for (const auto& m : rigid::bench::all_models())
    models.emplace_back(m.name);
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
        if (!rigid::bench::find_model(m)) {
          std::cerr << "memory_bench: --models: unknown model '" << m << "'\n";
          return 2;
        }
        models.push_back(m);
      }
    } else if (a == "--distinct") {
      distinct = true;
    } else {
      std::cerr << "usage: memory_bench [--bodies N] [--models general,isotropic,axisymmetric,"
                   "point,general_forced] [--distinct]\n";
      return a == "--help" || a == "-h" ? 0 : 2;
    }
  }
  for (const std::string& m : models) {
    const pid_t child = fork();
    if (child < 0) {
      std::perror("memory_bench: fork");
      return 1;
    }
    if (child == 0) _exit(measure(m, bodies, distinct));
    int status = 0;
    if (waitpid(child, &status, 0) != child || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
      std::cerr << "memory_bench: the run for '" << m << "' failed\n";
      return 1;
    }
  }
  return 0;
}
