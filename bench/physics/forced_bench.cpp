// Forced bodies: error against cost of chosen integrators on the loaded hard cases (thruster,
// symmetric top) and on a free one, side by side in one process. Cost: thread CPU time per
// body-step of a world of N copies, the integrators' timed runs interleaved and repeated, medians.
//
//   build/bench/forced_bench [--integrators a,b,...] [--cases thruster,symmetric_top,...]
//                            [--dt 1e-3] [--bodies 1000] [--repeats 5] [--references FILE]
//   build/bench/forced_bench --scaling 100000 [--threads 1,2] [--integrators hybrid4]
//     wall time per step of N thrusters (general body, body-fixed force) stepped by 1, 2, ...
//     threads (World::set_threads), the thread counts' timed runs interleaved, medians.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "hard_cases.hpp"

namespace {

using namespace rigid::bench;
using rigid::physics::World;

std::vector<std::string> split(const std::string& list) {
  std::vector<std::string> out;
  std::stringstream ss(list);
  for (std::string item; std::getline(ss, item, ',');) {
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

double error_of(const Case& c, const std::string& integrator, double dt, const Reference& r) {
  World w(world_spec(c, integrator, dt, 1));
  const long n = std::lround(c.duration / dt);
  Scorer score(c, r, n);
  BodyState s = w.state(0);
  for (long i = 1; i <= n; ++i) {
    w.step();
    s = w.state(0);
    score.observe(i, w.time(), s);
  }
  const Row row = score.result(s);
  return c.closed_form_drag ? row.err_x : row.err_q;
}

double wall_ns() {
  return std::chrono::duration<double, std::nano>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

int scaling(int bodies, const std::vector<int>& threads, const std::string& integrator,
            int repeats) {
  const Case* thruster = nullptr;
  const std::vector<Case> cases = hard_cases();
  for (const Case& c : cases) {
    if (c.name == "thruster") thruster = &c;
  }
  std::vector<World> worlds;
  for (int t : threads) {
    rigid::physics::WorldSpec ws = world_spec(*thruster, integrator, 1e-3, bodies);
    for (int i = 0; i < bodies; ++i)  // no two bodies alike
      ws.bodies[i].w_WB.x() += 1e-6 * (i % 1000);
    ws.threads = t;
    worlds.emplace_back(ws);
    worlds.back().step(2);
  }
  const long steps = std::max(5L, 20000000L / bodies);
  std::vector<std::vector<double>> ns(threads.size());
  for (int rep = 0; rep < repeats; ++rep) {
    for (std::size_t k = 0; k < worlds.size(); ++k) {
      const double t0 = wall_ns();
      worlds[k].step(steps);
      ns[k].push_back((wall_ns() - t0) / static_cast<double>(steps));
    }
  }
  std::printf("%-10s %8s %16s %12s %12s\n", "integrator", "threads", "wall us/step", "ns/body-step",
              "speed-up");
  double base = 0;
  for (std::size_t k = 0; k < threads.size(); ++k) {
    std::sort(ns[k].begin(), ns[k].end());
    const double med = ns[k][ns[k].size() / 2];
    if (k == 0) base = med;
    std::printf("%-10s %8d %16.1f %12.1f %12.2f\n", integrator.c_str(), threads[k], med / 1e3,
                med / bodies, base / med);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> integrators{"exact_rotor4", "rk4"};
  std::vector<std::string> cases{"thruster", "symmetric_top", "racket_flip"};
  double dt = 1e-3;
  int bodies = 1000, repeats = 5;
  long steps_per_run = 0;
  std::string references;
  int scaling_bodies = 0;
  std::vector<int> threads{1, 2};
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const auto next = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::cerr << "forced_bench: " << a << " needs a value\n";
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--integrators") {
      integrators = split(next());
    } else if (a == "--cases") {
      cases = split(next());
    } else if (a == "--dt") {
      dt = std::stod(next());
    } else if (a == "--bodies") {
      bodies = std::stoi(next());
    } else if (a == "--repeats") {
      repeats = std::stoi(next());
    } else if (a == "--steps") {
      steps_per_run = std::stol(next());
    } else if (a == "--scaling") {
      scaling_bodies = std::stoi(next());
    } else if (a == "--threads") {
      threads.clear();
      for (const std::string& t : split(next()))
        threads.push_back(std::stoi(t));
    } else if (a == "--references") {
      references = next();
    } else {
      std::cout << "usage: forced_bench [--integrators a,b] [--cases c,d] [--dt S] [--bodies N] "
                   "[--repeats R] [--steps S] [--references FILE]\n";
      return a == "--help" || a == "-h" ? 0 : 2;
    }
  }
  if (scaling_bodies > 0) {
    return scaling(
        scaling_bodies, threads,
        integrators.size() == 2 && integrators[0] == "exact_rotor4" ? "hybrid4" : integrators[0],
        repeats);
  }
  std::printf("%-16s %-16s %12s %12s %12s\n", "case", "integrator", "error", "ns/body-step",
              "ratio");
  for (const Case& c : hard_cases()) {
    if (std::find(cases.begin(), cases.end(), c.name) == cases.end()) continue;
    const Reference r = compute_reference(c, false, references);
    std::vector<double> err;
    for (const auto& name : integrators)
      err.push_back(error_of(c, name, dt, r));
    // Interleaved timed runs: each repetition times every integrator once.
    std::vector<World> worlds;
    for (const auto& name : integrators)
      worlds.emplace_back(world_spec(c, name, dt, bodies));
    const long steps = steps_per_run > 0 ? steps_per_run : std::max(20L, 2000000L / bodies);
    std::vector<std::vector<double>> ns(integrators.size());
    for (int rep = 0; rep < repeats; ++rep) {
      for (std::size_t k = 0; k < worlds.size(); ++k) {
        const double t0 = thread_cpu_ns();
        worlds[k].step(steps);
        ns[k].push_back((thread_cpu_ns() - t0) / (static_cast<double>(steps) * bodies));
      }
    }
    double base = 0;
    for (std::size_t k = 0; k < integrators.size(); ++k) {
      std::sort(ns[k].begin(), ns[k].end());
      const double med = ns[k][ns[k].size() / 2];
      if (k == 0) base = med;
      std::printf("%-16s %-16s %12.3e %12.1f %12.3f\n", c.name.c_str(), integrators[k].c_str(),
                  err[k], med, med / base);
    }
  }
  return 0;
}
