// Work-precision of the peer engines (MuJoCo, Bullet, ODE) on our hard cases, measured and scored
// exactly as bench/work_precision measures ours, into a CSV of the same columns: the integrator
// column is <engine>_<mode> (e.g. mujoco_rk4, bullet_gyro_implicit, ode_gyro).
//
//   build/bench/peers/peer_work_precision [--quick] [--out bench/results/peers.csv]
//       [--engines mujoco,bullet,ode] [--ours exact_rotor4,...|none] [--references FILE]
//
// Ours runs alongside (rows rigid_<integrator>; by default our default integrator alone), and the
// cost runs are interleaved: at each (case, step) every mode's first timed run, then every mode's
// second, and so on. A drift of the machine's speed during the run (other work, clock changes)
// then moves every mode's median alike, and the ratio of two modes' costs stays fair: the report's
// headline takes its cost ratios from these rows only.
//
// How each mode drives its engine is in bench/peers/README.md.
#include <algorithm>
#include <chrono>
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

std::vector<std::string> split(const std::string& list) {
  std::vector<std::string> out;
  std::stringstream ss(list);
  for (std::string item; std::getline(ss, item, ',');) {
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

// 1/60 s reads better than 0.0166667 in the progress lines.
std::string step_name(double dt) {
  return "1/" + std::to_string(std::lround(1.0 / dt)) + " s";
}

// One engine mode on one case: its rows, and the cost samples of each step until the median.
struct ModeRun {
  const PeerEngine* engine;
  std::string mode;
  std::vector<double> steps;              // ours from 1/10 s (our_sweep_steps), peers from 1/60 s
  std::vector<Row> rows;                  // per step
  std::vector<std::vector<double>> cost;  // per step, one sample per repeat
  std::string blowups;
  std::string integrator() const { return engine->name() + "_" + mode; }
  bool runs_at(double dt) const { return std::find(steps.begin(), steps.end(), dt) != steps.end(); }
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  std::string references;  // a cache shared with the other driver of a report run
  std::string out = "bench/results/peers.csv";
  std::set<std::string> wanted;
  std::vector<std::string> ours{std::string(rigid::physics::default_integrator().name)};
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--quick") {
      quick = true;
    } else if (a == "--out" && i + 1 < argc) {
      out = argv[++i];
    } else if (a == "--references" && i + 1 < argc) {
      references = argv[++i];
    } else if (a == "--engines" && i + 1 < argc) {
      for (const std::string& e : split(argv[++i]))
        wanted.insert(e);
    } else if (a == "--ours" && i + 1 < argc) {
      ours = split(argv[++i]);
      if (ours == std::vector<std::string>{"none"}) ours.clear();
    } else if (a == "--help" || a == "-h") {
      std::cout
          << "usage: peer_work_precision [--quick] [--out FILE.csv] "
             "[--engines mujoco,bullet,ode] [--ours INTEGRATOR,...|none] [--references CACHE]\n";
      return 0;
    } else {
      std::cerr << "peer_work_precision: unknown argument '" << a << "' (try --help)\n";
      return 2;
    }
  }
  for (const std::string& o : ours) {
    if (!rigid::physics::find_integrator(o)) {
      std::cerr << "peer_work_precision: --ours: unknown integrator '" << o << "'\n";
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
  const auto rigid_engine = make_rigid_engine();

  const std::string tmp = out + ".tmp";
  std::ofstream csv(tmp);
  if (!csv) {
    std::cerr << "peer_work_precision: cannot write '" << tmp << "'\n";
    return 1;
  }
  write_csv_header(csv);
  const int repeats = quick ? 1 : 3, copies = quick ? kQuickCopies : kCopies;
  const std::vector<double> steps = our_sweep_steps(quick);  // every run's steps are among these
  const auto start = std::chrono::steady_clock::now();
  const auto elapsed = [&] {
    const auto s =
        std::chrono::duration_cast<std::chrono::seconds>(std::chrono::steady_clock::now() - start)
            .count();
    return std::to_string(s / 60) + "m" + (s % 60 < 10 ? "0" : "") + std::to_string(s % 60) + "s";
  };
  for (const Case& c : hard_cases()) {
    const Reference reference = compute_reference(c, quick, references);
    std::vector<ModeRun> runs;
    for (const std::string& o : ours)
      runs.push_back({rigid_engine.get(), o, our_sweep_steps(quick), {}, {}, {}});
    for (const auto& e : engines) {
      for (const std::string& mode : e->modes(c))
        runs.push_back({e.get(), mode, sweep_steps(quick), {}, {}, {}});
    }
    for (double dt : steps) {
      int done = 0;
      for (ModeRun& m : runs) {
        if (!m.runs_at(dt)) continue;
        m.rows.push_back(accuracy_run(*m.engine, c, m.mode, dt, reference, copies));
        if (std::isinf(m.rows.back().err_q) || std::isinf(m.rows.back().err_x)) {
          m.blowups += (m.blowups.empty() ? "" : ", ") + step_name(dt);
        }
        m.cost.emplace_back();
        ++done;
      }
      for (int r = 0; r < repeats; ++r) {
        for (ModeRun& m : runs) {
          if (m.runs_at(dt)) m.cost.back().push_back(cost_run(*m.engine, c, m.mode, dt, 1, copies));
        }
      }
      std::cerr << "[peer_work_precision] " << c.name << " dt = " << step_name(dt) << ": " << done
                << " modes done (" << elapsed() << ")\n";
    }
    for (const ModeRun& m : runs) {
      for (std::size_t k = 0; k < m.steps.size(); ++k)
        write_csv_row(csv, c, m.integrator(), m.steps[k], m.rows[k], median(m.cost[k]),
                      reference.name);
      if (!m.blowups.empty()) {
        std::cerr << "[peer_work_precision] " << c.name << " / " << m.integrator()
                  << " blew up at dt = " << m.blowups << "\n";
      }
    }
    csv.flush();  // a long sweep's finished cases survive an interruption
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
  if (!ours.empty()) {
    versions += "ours in the same run, costs interleaved with the peers': rigid_<integrator>\n";
  }
  write_meta(out + ".meta", quick, copies, repeats, versions);
  std::cerr << "[peer_work_precision] wrote " << out << " and " << out << ".meta\n";
  return 0;
}
