// How the cost of one World::step spreads over the steps, not its mean: what rigidd's step-cost
// p99 is made of without its buses, timer or publishers. A world of N general bodies (the
// racket of model_worlds.cpp), every K-th of them forced (the thruster's load), on T threads, is
// stepped S times and each step timed alone. Work done once every few steps shows up as a step
// phase (step_count() % World::kGuardEvery) slower than the others: the guard once checked every
// body on every 64th step and so set the p99 by itself (World::guard_phase).
//
//   build/bench/step_percentiles [--bodies 10000] [--forced-every 3] [--threads 1]
//                                [--steps 19200]
//
// Pin it (taskset -c 0 for one thread) and compare builds side by side, alternated: the host
// drifts between runs. Output:
//   RESULT step_us p50 X p90 X p99 X max X (S steps, N bodies, F forced, T threads)
//   RESULT phase_median_us slowest X (phase P) median_of_phases X ratio X
#include <algorithm>
#include <charconv>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include "model_worlds.hpp"
#include "physics/world.hpp"

namespace {

using rigid::physics::World;
using rigid::physics::WorldSpec;

double percentile(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(p * static_cast<double>(v.size() - 1))];
}

bool parse(const char* flag, const std::string& v, int lo, int hi, int& out) {
  const auto [end, ec] = std::from_chars(v.data(), v.data() + v.size(), out);
  if (ec != std::errc() || end != v.data() + v.size() || out < lo || out > hi) {
    std::cerr << "step_percentiles: " << flag << ": expected " << lo << " .. " << hi << ", got '"
              << v << "'\n";
    return false;
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  int bodies = 10'000, forced_every = 3, threads = 1, steps = 300 * World::kGuardEvery;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has_value = i + 1 < argc;
    bool ok = true;
    if (a == "--bodies" && has_value) {
      ok = parse("--bodies", argv[++i], 1, 10'000'000, bodies);
    } else if (a == "--forced-every" && has_value) {
      ok = parse("--forced-every", argv[++i], 0, 10'000'000, forced_every);
    } else if (a == "--threads" && has_value) {
      ok = parse("--threads", argv[++i], 1, 256, threads);
    } else if (a == "--steps" && has_value) {
      ok = parse("--steps", argv[++i], World::kGuardEvery, 100'000'000, steps);
    } else {
      std::cerr << "usage: step_percentiles [--bodies N] [--forced-every K (0: none)] "
                   "[--threads T] [--steps S]\n";
      return a == "--help" || a == "-h" ? 0 : 2;
    }
    if (!ok) return 2;
  }

  using rigid::bench::Model;
  WorldSpec spec = rigid::bench::make_model_world(Model::kGeneral, bodies);
  int forced = 0;
  if (forced_every > 0) {
    // The thruster's load (the general_forced model's), on every forced_every-th body.
    const WorldSpec thrusters = rigid::bench::make_model_world(Model::kGeneralForced, 1);
    for (int i = 0; i < bodies; i += forced_every, ++forced) {
      auto load = thrusters.loads.front();
      load.body = i;
      spec.loads.push_back(load);
    }
  }
  World w(spec);
  w.set_threads(threads);
  w.step(World::kGuardEvery);  // plans made, pages touched

  std::vector<double> us(static_cast<std::size_t>(steps));
  std::vector<std::vector<double>> by_phase(World::kGuardEvery);
  for (int s = 0; s < steps; ++s) {
    const auto t0 = std::chrono::steady_clock::now();
    w.step();
    const auto t1 = std::chrono::steady_clock::now();
    const double x = std::chrono::duration<double, std::micro>(t1 - t0).count();
    us[static_cast<std::size_t>(s)] = x;
    by_phase[static_cast<std::size_t>(w.step_count() % World::kGuardEvery)].push_back(x);
  }
  std::printf(
      "RESULT step_us p50 %.1f p90 %.1f p99 %.1f max %.1f (%d steps, %d bodies, %d forced, %d "
      "threads)\n",
      percentile(us, 0.5), percentile(us, 0.9), percentile(us, 0.99),
      *std::max_element(us.begin(), us.end()), steps, bodies, forced, threads);
  std::vector<double> medians;
  int slowest = 0;
  for (int k = 0; k < World::kGuardEvery; ++k) {
    medians.push_back(percentile(by_phase[static_cast<std::size_t>(k)], 0.5));
    if (medians.back() > medians[static_cast<std::size_t>(slowest)]) slowest = k;
  }
  const double mid = percentile(medians, 0.5);
  std::printf("RESULT phase_median_us slowest %.1f (phase %d) median_of_phases %.1f ratio %.2f\n",
              medians[static_cast<std::size_t>(slowest)], slowest, mid,
              medians[static_cast<std::size_t>(slowest)] / mid);
  return 0;
}
