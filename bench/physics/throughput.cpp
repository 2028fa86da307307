// Throughput: the cost of World::step per body against the number of bodies N, for each body
// model and each integrator of ours, and the memory a World takes per body. One CSV row per
// (model, integrator, N); bench/report/plot_throughput.py draws it.
//
//   build/bench/throughput [--quick] [--out bench/results/throughput.csv] [--max-bodies N]
//                          [--integrators a,b,...]
//
// The models are one body of each of the four motion groups a World compiles bodies into
// (body_motion.hpp's BodyMotion), torque-free but for the point mass, which falls under gravity;
// and the general body again under an off-centre body-fixed force, where every integrator must
// evaluate the load at each of its stages. Bodies differ a little in their initial angular
// velocity so that no two are the same.
//
// Timing: thread CPU time of batches of steps, each batch at least 20 ms (quick: 5 ms), after one
// warm-up batch; the median over 5 batches (quick: 3), with the fastest and slowest beside it. CPU
// time rather than wall time, so that being descheduled by other work on a shared machine is not
// counted; memory stalls are, since the CPU waits for them.
//
// Memory: the heap a World allocates when it is built (glibc's count of bytes in use, before and
// after the constructor, the WorldSpec already built), and the resident set growth over that
// construction and its first step (pages actually touched), both per body.
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "hard_cases.hpp"  // thread_cpu_ns, write_meta
#include "model_worlds.hpp"
#include "physics/world.hpp"

namespace {

using rigid::bench::heap_bytes;
using rigid::bench::ModelInfo;
using rigid::bench::rss_bytes;
using rigid::physics::World;
using rigid::physics::WorldSpec;

struct Timing {
  double median = 0, fastest = 0, slowest = 0;
  long steps_per_batch = 0;
};

// Batches of steps of at least min_batch_ns of CPU time; the first batch is a warm-up.
Timing time_steps(World& w, int bodies, int batches, double min_batch_ns) {
  long steps = 1;
  for (;;) {  // warm-up, and the batch size: double until one batch lasts long enough
    const double t0 = rigid::bench::thread_cpu_ns();
    w.step(steps);
    const double t = rigid::bench::thread_cpu_ns() - t0;
    if (t >= min_batch_ns) break;
    steps =
        t <= 0 ? steps * 8 : std::max(steps * 2, static_cast<long>(steps * 1.2 * min_batch_ns / t));
  }
  std::vector<double> ns;
  for (int b = 0; b < batches; ++b) {
    const double t0 = rigid::bench::thread_cpu_ns();
    w.step(steps);
    ns.push_back((rigid::bench::thread_cpu_ns() - t0) / (static_cast<double>(steps) * bodies));
  }
  std::sort(ns.begin(), ns.end());
  return {ns[ns.size() / 2], ns.front(), ns.back(), steps};
}

std::vector<std::string> split(const std::string& list) {
  std::vector<std::string> out;
  std::stringstream ss(list);
  for (std::string item; std::getline(ss, item, ',');) {
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  std::string out = "bench/results/throughput.csv";
  long max_bodies = -1;
  std::vector<std::string> integrators;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--quick") {
      quick = true;
    } else if (a == "--out" && i + 1 < argc) {
      out = argv[++i];
    } else if (a == "--max-bodies" && i + 1 < argc) {
      max_bodies = std::stol(argv[++i]);
    } else if (a == "--integrators" && i + 1 < argc) {
      integrators = split(argv[++i]);
    } else if (a == "--help" || a == "-h") {
      std::cout << "usage: throughput [--quick] [--out FILE.csv] [--max-bodies N] "
                   "[--integrators a,b,...]\n";
      return 0;
    } else {
      std::cerr << "throughput: unknown argument '" << a << "' (try --help)\n";
      return 2;
    }
  }
  if (integrators.empty()) {
    if (quick) {
      integrators = {std::string(rigid::physics::default_integrator().name), "rk4"};
    } else {
      for (const auto& info : rigid::physics::all_integrators())
        integrators.emplace_back(info.name);
    }
  }
  for (const std::string& name : integrators) {
    if (!rigid::physics::find_integrator(name)) {
      std::cerr << "throughput: unknown integrator '" << name << "'\n";
      return 2;
    }
  }
  if (max_bodies < 0) max_bodies = quick ? 100000 : 1000000;
  std::vector<int> sizes;
  for (long n = 1; n <= max_bodies; n *= 10)
    sizes.push_back(static_cast<int>(n));
  const int batches = quick ? 3 : 5;
  const double min_batch_ns = quick ? 5e6 : 20e6;

  const std::string tmp = out + ".tmp";
  std::ofstream csv(tmp);
  if (!csv) {
    std::cerr << "throughput: cannot write '" << tmp << "'\n";
    return 1;
  }
  csv << "model,integrator,bodies,ns_per_body_step,ns_fastest,ns_slowest,batches,"
         "steps_per_batch,heap_bytes_per_body,rss_bytes_per_body\n";
  const auto start = std::chrono::steady_clock::now();
  for (const ModelInfo& m : rigid::bench::all_models()) {
    for (const int n : sizes) {
      WorldSpec spec = rigid::bench::make_model_world(m.model, n);
      for (const std::string& integrator : integrators) {
        spec.integrator = integrator;
        const double heap0 = heap_bytes(), rss0 = rss_bytes();
        World w(spec);
        const double heap = heap_bytes() - heap0;
        w.step();
        const double rss = rss_bytes() - rss0;
        const Timing t = time_steps(w, n, batches, min_batch_ns);
        char row[512];
        std::snprintf(row, sizeof row, "%s,%s,%d,%.4g,%.4g,%.4g,%d,%ld,%.1f,%.1f\n", m.name,
                      integrator.c_str(), n, t.median, t.fastest, t.slowest, batches,
                      t.steps_per_batch, heap / n, rss / n);
        csv << row;
      }
      csv.flush();
      const auto s =
          std::chrono::duration_cast<std::chrono::seconds>(std::chrono::steady_clock::now() - start)
              .count();
      std::cerr << "[throughput] " << m.name << " N = " << n << ": " << integrators.size()
                << " integrators done (" << s << " s)\n";
    }
  }
  csv.close();
  if (std::rename(tmp.c_str(), out.c_str()) != 0) {
    std::cerr << "throughput: cannot rename '" << tmp << "' to '" << out << "'\n";
    return 1;
  }
  std::string models;
  for (const ModelInfo& m : rigid::bench::all_models())
    models += "model " + std::string(m.name) + ": " + m.body + "\n";
  rigid::bench::write_meta(
      out + ".meta", quick, 0, batches,
      models + "cost: thread CPU time per body-step, median of " + std::to_string(batches) +
          " batches of >= " + std::to_string(static_cast<int>(min_batch_ns / 1e6)) + " ms\n");
  std::cerr << "[throughput] wrote " << out << " and " << out << ".meta\n";
  return 0;
}
