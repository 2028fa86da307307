// Cost of World::step per body, by case and integrator (Google Benchmark).
//
//   build/bench/step_bench --benchmark_filter='racket|sphere' --benchmark_repetitions=5
//       --benchmark_report_aggregates_only=true         (one command line)
//
// Each world holds N bodies of one case (step_worlds.hpp), with initial conditions spread a little
// so that no two bodies are identical. The counter ns_per_body_step is the wall time of one step
// divided by N.
#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "physics/free_rotor.hpp"
#include "physics/world.hpp"
#include "step_worlds.hpp"

namespace {

using rigid::physics::Quat;
using rigid::physics::Vec3;
using rigid::physics::World;
using rigid::physics::WorldSpec;

using rigid::bench::make_step_world;
using Case = rigid::bench::StepCase;

void BM_Step(benchmark::State& state, Case c, std::string integrator) {
  const int n = static_cast<int>(state.range(0));
  World w(make_step_world(c, n, integrator));
  w.step(2);
  for (auto _ : state) {
    w.step();
    benchmark::ClobberMemory();
  }
  // A rate of (body-steps * 1e-9) per second, inverted: nanoseconds per body-step.
  state.counters["ns_per_body_step"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * n * 1e-9,
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// Cost per body of World::write_states, the daemon's state message and Python's arrays: every
// body's pose and velocities in the world frame, written in body-id order, on 1 or 2 threads
// (the world's; 10^3 bodies are written on the calling thread alone either way).
void BM_WriteStates(benchmark::State& state, Case c) {
  const int n = static_cast<int>(state.range(0));
  WorldSpec ws = make_step_world(c, n, "hybrid4");
  ws.threads = static_cast<int>(state.range(1));
  World w(ws);
  w.step(2);
  std::vector<double> p(3 * n), q(4 * n), v(3 * n), o(3 * n);
  for (auto _ : state) {
    w.write_states({p.data(), q.data(), v.data(), o.data()});
    benchmark::ClobberMemory();
  }
  state.counters["ns_per_body"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * n * 1e-9,
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// One torque-free long step of the exact rotor with its plan cached (a free body at a long dt):
// psi in closed form (the default) or by Gauss-Legendre panels (the fallback), side by side.
void BM_RotorLongStep(benchmark::State& state, Vec3 w0, double h, bool closed) {
  const Vec3 I(1, 2, 3);
  const rigid::physics::RotorInertia J(I);
  Vec3 m = I.cwiseProduct(w0);
  rigid::physics::RotorPlan p;
  rigid::physics::make_rotor_plan(J, m, h, p);
  if (!closed) p.closed = false;
  Quat q = Quat::Identity();
  for (auto _ : state) {
    Quat dq;
    rigid::physics::advance_rotor(p, m, dq, rigid::physics::RotorUpdate::kPinned);
    q = q * dq;
    benchmark::DoNotOptimize(q);
  }
  state.counters["ns_per_step"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * 1e-9,
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

void register_all() {
  const std::pair<Vec3, const char*> spins[] = {{Vec3(20, 0.5, 20), "fast_spin"},
                                                {Vec3(1e-3, 5, 1e-3), "racket"}};
  for (const auto& [w0, name] : spins) {
    for (const double h : {1.0 / 60, 0.1, 1.0}) {
      for (const bool closed : {true, false}) {
        benchmark::RegisterBenchmark(
            (std::string("rotor_long/") + name + "/h=" + std::to_string(h).substr(0, 6) +
             (closed ? "/closed" : "/panels"))
                .c_str(),
            BM_RotorLongStep, w0, h, closed);
      }
    }
  }
  const std::pair<Case, const char*> cases[] = {{Case::kRacket, "racket"},
                                                {Case::kSphere, "sphere"},
                                                {Case::kTop, "top"},
                                                {Case::kPoint, "point"},
                                                {Case::kThruster, "thruster"}};
  const char* integrators[] = {"hybrid4", "exact_rotor4",  "exact_rotor", "rk4",
                               "dlm",     "implicit_gyro", "games103"};
  for (const auto& [c, cname] : cases) {
    benchmark::RegisterBenchmark((std::string("write_states/") + cname).c_str(), BM_WriteStates, c)
        ->ArgsProduct({{1000, 100000}, {1, 2}})
        ->ArgNames({"", "threads"})
        ->Unit(benchmark::kMicrosecond);
    for (const char* integ : integrators) {
      benchmark::RegisterBenchmark((std::string(cname) + "/" + integ).c_str(), BM_Step, c,
                                   std::string(integ))
          ->Arg(1000)
          ->Arg(10000)
          ->Unit(benchmark::kMicrosecond);
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  register_all();
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
}
