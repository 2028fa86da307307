// Work-precision of the peer engines (MuJoCo, Bullet, ODE) on our hard cases, measured and scored
// exactly as bench/work_precision measures ours, into a CSV of the same columns: the integrator
// column is <engine>_<mode> (e.g. mujoco_rk4, bullet_gyro_implicit, ode_gyro).
//
//   build/bench/peers/peer_work_precision [--quick] [--out bench/results/peers.csv]
//                                         [--engines mujoco,bullet,ode]
//
// How each mode drives its engine is in bench/peers/README.md.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "peer_engine.hpp"
#include "peer_run.hpp"

namespace {

using namespace rigid::bench;
using namespace rigid::bench::peers;

std::set<std::string> split(const std::string& list) {
  std::set<std::string> out;
  std::stringstream ss(list);
  for (std::string item; std::getline(ss, item, ',');) {
    if (!item.empty()) out.insert(item);
  }
  return out;
}

// 1/60 s reads better than 0.0166667 in the progress lines.
std::string step_name(double dt) {
  return "1/" + std::to_string(std::lround(1.0 / dt)) + " s";
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  std::string out = "bench/results/peers.csv";
  std::set<std::string> wanted;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--quick") {
      quick = true;
    } else if (a == "--out" && i + 1 < argc) {
      out = argv[++i];
    } else if (a == "--engines" && i + 1 < argc) {
      wanted = split(argv[++i]);
    } else if (a == "--help" || a == "-h") {
      std::cout << "usage: peer_work_precision [--quick] [--out FILE.csv] "
                   "[--engines mujoco,bullet,ode]\n";
      return 0;
    } else {
      std::cerr << "peer_work_precision: unknown argument '" << a << "' (try --help)\n";
      return 2;
    }
  }

  std::vector<std::unique_ptr<PeerEngine>> engines;
  std::set<std::string> built;
  for (auto& e : built_engines()) {
    built.insert(e->name());
    if (wanted.empty() || wanted.count(e->name())) engines.push_back(std::move(e));
  }
  for (const std::string& w : wanted) {
    if (!built.count(w)) {
      std::cerr << "peer_work_precision: engine '" << w
                << "' is not built (its development package was not found at configure time)\n";
      return 2;
    }
  }
  if (engines.empty()) {
    std::cerr << "peer_work_precision: no peer engine is built\n";
    return 2;
  }

  const std::string tmp = out + ".tmp";
  std::ofstream csv(tmp);
  if (!csv) {
    std::cerr << "peer_work_precision: cannot write '" << tmp << "'\n";
    return 1;
  }
  write_csv_header(csv);
  const int repeats = quick ? 1 : 3;
  for (const Case& c : hard_cases()) {
    const Reference reference = compute_reference(c, quick);
    for (const auto& e : engines) {
      for (const std::string& mode : e->modes(c)) {
        const std::string integrator = e->name() + "_" + mode;
        std::string blowups;
        for (double dt : sweep_steps(quick)) {
          const Row row = accuracy_run(*e, c, mode, dt, reference);
          const double ns = cost_run(*e, c, mode, dt, repeats);
          if (std::isinf(row.err_q) || std::isinf(row.err_x)) {
            blowups += (blowups.empty() ? "" : ", ") + step_name(dt);
          }
          write_csv_row(csv, c, integrator, dt, row, ns, reference.name);
          csv.flush();  // a long sweep's partial results survive an interruption
        }
        std::cerr << "[peer_work_precision] " << c.name << " / " << integrator << " done";
        if (!blowups.empty()) std::cerr << " (blew up at dt = " << blowups << ")";
        std::cerr << "\n";
      }
    }
  }
  csv.close();
  if (std::rename(tmp.c_str(), out.c_str()) != 0) {
    std::cerr << "peer_work_precision: cannot rename '" << tmp << "' to '" << out << "'\n";
    return 1;
  }
  std::string versions;
  for (const auto& e : engines)
    versions += "peer " + e->name() + ": " + e->version() + "\n";
  versions += "peer modes: as bench/peers/README.md describes; integrator = <engine>_<mode>\n";
  write_meta(out + ".meta", quick, versions);
  std::cerr << "[peer_work_precision] wrote " << out << " and " << out << ".meta\n";
  return 0;
}
