// The five classic contact cases for ours and for MuJoCo, Bullet and ODE side by side, at dt = 1
// ms, 1/240 s and 1/60 s, into one CSV row per (case, engine mode, dt): impact-time errors,
// penetration, apex and energy errors, rest or stop time, stop distance, drift at rest, and the
// cost per body-step: over the run, over its steps after 1 s (once settled), and without the plane
// (a free body of the same model).
//
//   build/bench/peers/peer_contacts [--quick] [--out bench/results/contacts.csv]
//       [--engines rigid,mujoco,bullet,ode] [--cases NAME,...]
//
// The cost runs are interleaved: at each (case, dt) every mode's first timed run (with the plane,
// then without), then every mode's second, and so on, so that a drift of the machine's speed
// moves every median alike. What is measured and how each engine is driven: README.md.
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

#include "contact_engine.hpp"
#include "contact_run.hpp"
#include "contact_score.hpp"

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

std::string step_name(double dt) {
  return dt == 1e-3 ? "1 ms" : "1/" + std::to_string(std::lround(1.0 / dt)) + " s";
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

struct ModeRun {
  const ContactEngine* engine;
  std::string mode;
  ContactRow row;
  std::vector<double> cost, settled_cost, free_cost;
  std::string name() const { return engine->name() + "_" + mode; }
};

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  std::string out = "bench/results/contacts.csv";
  std::set<std::string> wanted_engines, wanted_cases;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--quick") {
      quick = true;
    } else if (a == "--out" && i + 1 < argc) {
      out = argv[++i];
    } else if (a == "--engines" && i + 1 < argc) {
      for (const std::string& e : split(argv[++i]))
        wanted_engines.insert(e);
    } else if (a == "--cases" && i + 1 < argc) {
      for (const std::string& c : split(argv[++i]))
        wanted_cases.insert(c);
    } else if (a == "--help" || a == "-h") {
      std::cout << "usage: peer_contacts [--quick] [--out FILE.csv] "
                   "[--engines rigid,mujoco,bullet,ode] [--cases NAME,...]\n";
      return 0;
    } else {
      std::cerr << "peer_contacts: unknown argument '" << a << "' (try --help)\n";
      return 2;
    }
  }

  std::vector<std::unique_ptr<ContactEngine>> engines;
  engines.push_back(make_rigid_contact_engine());
  for (auto& e : built_contact_engines())
    engines.push_back(std::move(e));
  std::set<std::string> built;
  for (const auto& e : engines)
    built.insert(e->name());
  for (const std::string& w : wanted_engines) {
    if (!built.count(w)) {
      std::cerr << "peer_contacts: --engines: '" << w
                << "' is not built (its development package was not found at configure time)\n";
      return 2;
    }
  }
  std::erase_if(engines, [&](const auto& e) {
    return !wanted_engines.empty() && !wanted_engines.count(e->name());
  });
  std::vector<ContactCase> cases = contact_cases();
  std::set<std::string> known;
  for (const ContactCase& c : cases)
    known.insert(c.name);
  for (const std::string& w : wanted_cases) {
    if (!known.count(w)) {
      std::cerr << "peer_contacts: --cases: unknown case '" << w << "'\n";
      return 2;
    }
  }
  std::erase_if(cases, [&](const ContactCase& c) {
    return !wanted_cases.empty() && !wanted_cases.count(c.name);
  });

  const std::string tmp = out + ".tmp";
  std::ofstream csv(tmp);
  if (!csv) {
    std::cerr << "peer_contacts: cannot write '" << tmp << "'\n";
    return 1;
  }
  write_contact_csv_header(csv);
  const int repeats = quick ? 1 : 5, copies = quick ? kQuickCopies : kCopies;
  // Each timed sample is at least this much CPU time: ours at 1/60 s steps a world of 32 bodies
  // through a case in ~0.1 ms, too short to time alone.
  const double min_ns = quick ? 2e6 : 20e6;
  const std::vector<double> steps = {1e-3, 1.0 / 240, 1.0 / 60};
  const auto start = std::chrono::steady_clock::now();
  const auto elapsed = [&] {
    const auto s =
        std::chrono::duration_cast<std::chrono::seconds>(std::chrono::steady_clock::now() - start)
            .count();
    return std::to_string(s / 60) + "m" + (s % 60 < 10 ? "0" : "") + std::to_string(s % 60) + "s";
  };
  for (const ContactCase& c : cases) {
    const ContactCase free = without_plane(c);
    for (double dt : steps) {
      std::vector<ModeRun> runs;
      for (const auto& e : engines) {
        for (const std::string& m : e->modes())
          runs.push_back({e.get(), m, {}, {}, {}, {}});
      }
      for (ModeRun& r : runs)
        r.row = contact_accuracy_run(*r.engine, c, r.mode, dt);
      for (int k = 0; k < repeats; ++k) {
        for (ModeRun& r : runs) {
          const ContactCost with = contact_cost_run(*r.engine, c, r.mode, dt, copies, min_ns);
          r.cost.push_back(with.ns_per_body_step);
          r.settled_cost.push_back(with.settled_ns_per_body_step);
          r.free_cost.push_back(
              contact_cost_run(*r.engine, free, r.mode, dt, copies, min_ns).ns_per_body_step);
        }
      }
      for (const ModeRun& r : runs) {
        write_contact_csv_row(csv, c, r.name(), dt, contact_steps(c, dt), r.row, median(r.cost),
                              median(r.settled_cost), median(r.free_cost));
      }
      csv.flush();
      std::cerr << "[peer_contacts] " << c.name << " dt = " << step_name(dt) << ": " << runs.size()
                << " modes done (" << elapsed() << ")\n";
    }
  }
  csv.close();
  if (std::rename(tmp.c_str(), out.c_str()) != 0) {
    std::cerr << "peer_contacts: cannot rename '" << tmp << "' to '" << out << "'\n";
    return 1;
  }
  std::ostringstream extra;
  for (const auto& e : engines) {
    extra << "engine " << e->name() << ": " << e->version() << "\n";
    for (const std::string& m : e->modes())
      extra << "mode " << e->name() << "_" << m << ": " << e->settings(m) << "\n";
  }
  for (const ContactCase& c : cases)
    extra << "case " << c.name << ": " << c.description << "\n";
  extra << "rules: as bench/peers/README.md (Contacts) says; impacts from located events where "
           "an engine has them, else the middle of the step over which the vertical velocity "
           "turns up after a descent of at least "
        << kRestSpeed << " m/s; rest: the first state after the last one whose speed bound "
        << "|v| + |w| r is at least " << kRestSpeed << " m/s, or the resting event\n";
  extra << "each timed sample: fresh worlds stepped through the case until at least "
        << min_ns / 1e6 << " ms of CPU time\n";
  write_meta(out + ".meta", quick, copies, repeats, extra.str());
  std::cerr << "[peer_contacts] wrote " << out << " and " << out << ".meta\n";
  return 0;
}
