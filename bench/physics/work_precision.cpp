// Work-precision: the error of every integrator of ours against its cost, on the hard cases
// (bench/physics/hard_cases.hpp), for steps from 1/10 s to 1/10000 s. One CSV row per (case, integrator,
// step); bench/report/plot_work_precision.py turns it into plots and tables.
//
//   build/bench/work_precision [--quick] [--out bench/results/work_precision.csv] [--references F]
//
// Cost is the thread CPU time of stepping a world of kCopies (quick: kQuickCopies) identical
// bodies, per body and per simulated second (median of repeats), so that it reads on the same axis
// as any other engine's. --references shares the hard cases' references with peer_work_precision.
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "hard_cases.hpp"

namespace {

using namespace rigid::bench;
using rigid::physics::World;
using rigid::physics::WorldSpec;

// Accuracy run (body 0 observed every step) and cost runs (median of repeats).
void run(std::ostream& csv, const Case& c, const std::string& integrator, double dt,
         const Reference& reference, int copies, int repeats) {
  const WorldSpec ws = world_spec(c, integrator, dt, copies);
  const long n = std::lround(c.duration / dt);
  World w(ws);
  Scorer score(c, reference, n);
  BodyState prev = w.state(0), s = prev;
  for (long i = 1; i <= n && !score.failed(); ++i) {
    w.step();
    s = w.state(0);
    // The peers' rule for a blow-up, and the World's guard, which freezes a diverging body.
    if (w.is_frozen(0) || blown_up(s, prev, dt)) s = nan_state();
    score.observe(i, w.time(), s);
    prev = s;
  }
  const Row row = score.result(s);
  std::vector<double> t;
  for (int r = 0; r < repeats; ++r) {
    World cost(ws);
    const double t0 = thread_cpu_ns();
    cost.step(n);
    t.push_back((thread_cpu_ns() - t0) / (static_cast<double>(n) * copies));
  }
  std::sort(t.begin(), t.end());
  write_csv_row(csv, c, integrator, dt, row, t[t.size() / 2], reference.name);
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  std::string references;  // a cache shared with the other driver of a report run
  std::string out = "bench/results/work_precision.csv";
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--quick") {
      quick = true;
    } else if (a == "--out" && i + 1 < argc) {
      out = argv[++i];
    } else if (a == "--references" && i + 1 < argc) {
      references = argv[++i];
    } else if (a == "--help" || a == "-h") {
      std::cout << "usage: work_precision [--quick] [--out FILE.csv] [--references CACHE]\n";
      return 0;
    } else {
      std::cerr << "work_precision: unknown argument '" << a << "' (try --help)\n";
      return 2;
    }
  }
  const std::string tmp = out + ".tmp";
  std::ofstream csv(tmp);
  if (!csv) {
    std::cerr << "work_precision: cannot write '" << tmp << "'\n";
    return 1;
  }
  write_csv_header(csv);
  const int copies = quick ? kQuickCopies : kCopies, repeats = quick ? 1 : 3;
  for (const Case& c : hard_cases()) {
    const Reference reference = compute_reference(c, quick, references);
    for (const auto& info : rigid::physics::all_integrators()) {
      for (double dt : our_sweep_steps(quick))
        run(csv, c, std::string(info.name), dt, reference, copies, repeats);
      std::cerr << "[work_precision] " << c.name << " / " << info.name << " done\n";
    }
  }
  csv.close();
  if (std::rename(tmp.c_str(), out.c_str()) != 0) {
    std::cerr << "work_precision: cannot rename '" << tmp << "' to '" << out << "'\n";
    return 1;
  }
  std::string cases;  // for the report: what each case is
  for (const Case& c : hard_cases())
    cases += "case " + c.name + ": " + c.description + "\n";
  write_meta(out + ".meta", quick, copies, repeats, cases);
  std::cerr << "[work_precision] wrote " << out << " and " << out << ".meta\n";
  return 0;
}
