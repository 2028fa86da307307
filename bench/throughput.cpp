// Throughput: the cost of World::step per body against the number of bodies N, for each body
// model and each integrator of ours, and the memory a World takes per body. One CSV row per
// (model, integrator, N); bench/plot_throughput.py draws it.
//
//   build/bench/throughput [--quick] [--out bench/results/throughput.csv] [--max-bodies N]
//                          [--integrators a,b,...]
//
// The models are the four a World compiles bodies into (world.hpp's BodyModel), torque-free but
// for the point mass, which falls under gravity; and the general body again under an off-centre
// body-fixed force, where every integrator must evaluate the load at each of its stages. Bodies
// differ a little in their initial angular velocity so that no two are the same.
//
// Timing: thread CPU time of batches of steps, each batch at least 20 ms (quick: 5 ms), after one
// warm-up batch; the median over 5 batches (quick: 3), with the fastest and slowest beside it. CPU
// time rather than wall time, so that being descheduled by other work on a shared machine is not
// counted; memory stalls are, since the CPU waits for them.
//
// Memory: the heap a World allocates when it is built (glibc's count of bytes in use, before and
// after the constructor, the WorldSpec already built), and the resident set growth over that
// construction and its first step (pages actually touched), both per body.
#include <malloc.h>
#include <time.h>
#include <unistd.h>

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
#include "physics/world.hpp"

namespace {

using rigid::physics::BodySpec;
using rigid::physics::Frame;
using rigid::physics::LoadSpec;
using rigid::physics::Vec3;
using rigid::physics::World;
using rigid::physics::WorldSpec;

enum class Model { kPoint, kIsotropic, kAxisymmetric, kGeneral, kGeneralForced };

struct ModelInfo {
  Model model;
  const char* name;
  const char* body;  // for the report
};

constexpr ModelInfo kModels[] = {
    {Model::kPoint, "point", "point mass under gravity"},
    {Model::kIsotropic, "isotropic", "I = 0.4 (1, 1, 1), w0 = (1, 2, 3), moving"},
    {Model::kAxisymmetric, "axisymmetric", "I = (1, 1, 1.8), w0 = (1, 0, 20)"},
    {Model::kGeneral, "general", "racket: I = (1, 2, 3), w0 = (1e-3, 5, 1e-3)"},
    {Model::kGeneralForced, "general_forced",
     "thruster: I = (0.5, 1, 1.3), m = 2, f_B = (0, 0, 4) at (0.4, 0.1, 0)"},
};

WorldSpec make_spec(Model model, int n) {
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
  for (const ModelInfo& m : kModels) {
    for (const int n : sizes) {
      WorldSpec spec = make_spec(m.model, n);
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
  for (const ModelInfo& m : kModels)
    models += "model " + std::string(m.name) + ": " + m.body + "\n";
  rigid::bench::write_meta(
      out + ".meta", quick, 0, batches,
      models + "cost: thread CPU time per body-step, median of " + std::to_string(batches) +
          " batches of >= " + std::to_string(static_cast<int>(min_batch_ns / 1e6)) + " ms\n");
  std::cerr << "[throughput] wrote " << out << " and " << out << ".meta\n";
  return 0;
}
