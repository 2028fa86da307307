// Work-precision: the error of every integrator against its cost, on the hard cases, for steps
// from 1/60 s to 1/10000 s. Writes one CSV row per (case, integrator, step):
//
//   build/bench/work_precision [--quick] [--out bench/results/work_precision.csv]
//
// Error is taken against an independent long-double RK4 run at a step 100x finer or more
// (tests/physics/reference.hpp; converged to < 1e-15), or against the closed form where one exists
// (stiff drag); the column `reference` says which. Cost is the thread CPU time of stepping a world
// of kCopies identical bodies, per body and per simulated second (median of repeats), so that it
// can be read against any other engine's cost on the same axis.
#include <sys/utsname.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <iostream>
#include <string>
#include <vector>

#include "physics/world.hpp"
#include "reference.hpp"  // tests/physics: the independent long-double oracle

namespace {

using rigid::physics::BodySpec;
using rigid::physics::BodyState;
using rigid::physics::Frame;
using rigid::physics::LoadSpec;
using rigid::physics::Quat;
using rigid::physics::Vec3;
using rigid::physics::World;
using rigid::physics::WorldSpec;
namespace ref = rigid::test;

constexpr int kCopies = 32;

double thread_cpu_ns() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return 1e9 * static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_nsec);
}

double angle_between(const Quat& a, const Quat& b) {
  const Quat d = a.conjugate() * b;
  return 2.0 * std::atan2(d.vec().norm(), std::abs(d.w()));
}

Vec3 to_double(const ref::V3& v) {
  return Vec3(double(v.x()), double(v.y()), double(v.z()));
}
Quat to_double(const ref::Q4& q) {
  return Quat(double(q.w()), double(q.x()), double(q.y()), double(q.z())).normalized();
}
ref::V3 to_ld(const Vec3& v) {
  return ref::V3(v.x(), v.y(), v.z());
}

// One hard case: a single body, its loads, and the oracle.
struct Case {
  std::string name;
  std::string description;
  double duration = 5.0;
  BodySpec body;
  std::vector<LoadSpec> loads;  // on body 0; replicated for each copy
  ref::RefBody oracle;          // the same body for the long-double reference
  long reference_steps = 1000000;
  bool closed_form_drag = false;  // stiff drag: scored against the closed form along the path
  bool conservative = true;       // energy and momentum (or energy) are invariants to report
  bool torque_free = false;       // scored against the quad-precision Taylor series
};

BodySpec make_body(const Vec3& I, const Vec3& w0) {
  BodySpec b;
  b.name = "b";
  b.mass = 1.0;
  b.I_B = I.asDiagonal();
  b.w_WB = w0;
  b.use_gravity = false;
  return b;
}

std::vector<Case> hard_cases() {
  std::vector<Case> cases;
  const auto free_case = [&](std::string name, std::string desc, Vec3 I, Vec3 w0, double T,
                             long nref) {
    Case c;
    c.name = std::move(name);
    c.description = std::move(desc);
    c.duration = T;
    c.body = make_body(I, w0);
    c.oracle.I = to_ld(I);
    c.reference_steps = nref;
    c.torque_free = true;
    cases.push_back(c);
  };
  free_case("racket_flip", "tennis-racket flip: I = (1, 2, 3), w0 = (1e-3, 5, 1e-3), 20 s",
            {1, 2, 3}, {1e-3, 5, 1e-3}, 20.0, 2000000);
  free_case("near_separatrix",
            "closer to the separatrix: I = (1, 2, 3), w0 = (1e-6, 5, 1e-6), 20 s", {1, 2, 3},
            {1e-6, 5, 1e-6}, 20.0, 2000000);
  free_case("fast_spin", "fast spin: I = (1, 2, 3), w0 = (20, 0.5, 20), 5 s", {1, 2, 3},
            {20, 0.5, 20}, 5.0, 2000000);
  free_case("thin_rod", "thin rod: I = (1e-4, 1, 1), w0 = (50, 1, 0.2), 5 s", {1e-4, 1, 1},
            {50, 1, 0.2}, 5.0, 2000000);
  {
    // A symmetric top driven by a constant world-frame force at a point on its axis: the torque
    // (R r) x f of a heavy top, conservative (potential -f . (x + R r)), with fast spin.
    Case c;
    c.name = "symmetric_top";
    c.description =
        "symmetric top precessing under a world force at its axis: I = (1, 1, 0.4), "
        "w0 = (0.5, 0.2, 30), f = (0, 0, -9.81) at (0, 0, 0.3), 5 s";
    c.body = make_body({1, 1, 0.4}, {0.5, 0.2, 30});
    c.loads.push_back(LoadSpec{.body = 0, .force = {0, 0, -9.81}, .p_BoQ_B = {0, 0, 0.3}});
    c.oracle.I = ref::V3(1, 1, 0.4);
    c.oracle.f_W = ref::V3(0, 0, -9.81);
    c.oracle.r_fW = ref::V3(0, 0, 0.3);
    c.reference_steps = 2000000;
    cases.push_back(c);
  }
  {
    Case c;
    c.name = "thruster";
    c.description =
        "off-centre body-fixed thruster: I = (0.5, 1, 1.3), m = 2, w0 = (0.2, 0.1, 1), "
        "f_B = (0, 0, 4) at (0.4, 0.1, 0), 5 s";
    c.body = make_body({0.5, 1.0, 1.3}, {0.2, 0.1, 1.0});
    c.body.mass = 2.0;
    c.loads.push_back(
        LoadSpec{.body = 0, .force = {0, 0, 4}, .p_BoQ_B = {0.4, 0.1, 0}, .frame = Frame::kBody});
    c.oracle.I = ref::V3(0.5, 1.0, 1.3);
    c.oracle.mass = 2;
    c.oracle.f_B = ref::V3(0, 0, 4);
    c.oracle.r_fB = ref::V3(0.4, 0.1, 0);
    c.conservative = false;
    cases.push_back(c);
  }
  {
    // Linear drag c = 500 N s/m on 1 kg: c dt / m = 8.3 at 1/60 s, 0.5 at 1/1000 s.
    Case c;
    c.name = "stiff_drag";
    c.description =
        "stiff drag: m = 1, c = 500, gravity, v0 = (10, 0, 5), 1 s; worst position "
        "error along the path against the closed form";
    c.duration = 1.0;
    c.body = make_body({0.4, 0.4, 0.4}, {0, 0, 0});
    c.body.linear_drag = 500.0;
    c.body.use_gravity = true;
    c.body.v_WBo = {10, 0, 5};
    c.closed_form_drag = true;
    c.conservative = false;
    cases.push_back(c);
  }
  return cases;
}

struct Row {
  double err_q = NAN, err_w = NAN, err_x = NAN, energy = NAN, momentum = NAN,
         ns_per_body_step = NAN;
};

// The closed form of v' = g - (c/m) v from v0, and its position.
Vec3 drag_position(const Case& c, const Vec3& g, double t) {
  const double k = c.body.linear_drag / c.body.mass, e = std::exp(-k * t);
  const Vec3 vinf = g / k;
  return vinf * t + (c.body.v_WBo - vinf) * (1 - e) / k;
}

Row run(const Case& c, const std::string& integrator, double dt, const ref::RefState& reference,
        int repeats) {
  WorldSpec ws;
  ws.dt = dt;
  ws.integrator = integrator;
  ws.g_W = c.body.use_gravity ? Vec3(0, 0, -9.81) : Vec3::Zero();
  for (int k = 0; k < kCopies; ++k) {
    BodySpec b = c.body;
    b.name = "b" + std::to_string(k);
    ws.bodies.push_back(b);
    for (LoadSpec l : c.loads) {
      l.body = k;
      ws.loads.push_back(l);
    }
  }
  const long n = std::lround(c.duration / dt);
  Row row;
  // Accuracy run (body 0), sampling invariants along the way.
  {
    World w(ws);
    const Vec3 L0 = w.angular_momentum_W(0);
    const auto energy = [&] {
      double e = w.kinetic_energy(0) - w.body_spec(0).mass * ws.g_W.dot(w.state(0).p_WBo);
      for (const LoadSpec& l : c.loads) {  // potential of constant world forces at points
        if (l.body != 0 || l.frame != Frame::kWorld) continue;
        const BodyState s = w.state(0);
        e -= l.force.dot(s.p_WBo + s.q_WB * l.p_BoQ_B);
      }
      return e;
    };
    const double E0 = energy();
    double worst_x = 0, worst_E = 0, worst_L = 0;
    const long every = std::max(1L, n / 200);
    for (long i = 1; i <= n; ++i) {
      w.step();
      if (c.closed_form_drag) {
        worst_x = std::max(worst_x, (w.state(0).p_WBo - drag_position(c, ws.g_W, w.time())).norm());
        if (!std::isfinite(worst_x)) break;
      }
      if (c.conservative && (i % every == 0 || i == n)) {
        worst_E = std::max(worst_E, std::abs(energy() - E0) / std::abs(E0));
        if (c.loads.empty()) {
          worst_L = std::max(worst_L, (w.angular_momentum_W(0) - L0).norm() / L0.norm());
        }
      }
    }
    const BodyState s = w.state(0);
    if (c.closed_form_drag) {
      row.err_x = worst_x;
    } else {
      row.err_q = angle_between(s.q_WB, to_double(reference.q));
      row.err_w = (s.w_WB - to_double(reference.q) * to_double(reference.w)).norm();
      row.err_x = (s.p_WBo - to_double(reference.x)).norm();
    }
    if (c.conservative) {
      row.energy = worst_E;
      if (c.loads.empty()) row.momentum = worst_L;
    }
  }
  // Cost runs: the whole world, thread CPU time, median of repeats.
  std::vector<double> t;
  for (int r = 0; r < repeats; ++r) {
    World w(ws);
    const double t0 = thread_cpu_ns();
    w.step(n);
    t.push_back((thread_cpu_ns() - t0) / (static_cast<double>(n) * kCopies));
  }
  std::sort(t.begin(), t.end());
  row.ns_per_body_step = t[t.size() / 2];
  return row;
}

// What the figures must say about where they come from: machine, compiler, flags, date.
void write_meta(const std::string& path, bool quick) {
  std::ofstream m(path);
  std::string cpu = "unknown";
  std::ifstream info("/proc/cpuinfo");
  for (std::string line; std::getline(info, line);) {
    if (line.rfind("model name", 0) == 0) {
      cpu = line.substr(line.find(':') + 2);
      break;
    }
  }
  utsname u{};
  uname(&u);
  char date[64];
  const time_t now = time(nullptr);
  strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", gmtime(&now));
  m << "cpu: " << cpu << "\n"
    << "cores: " << sysconf(_SC_NPROCESSORS_ONLN) << "\n"
    << "kernel: " << u.sysname << ' ' << u.release << "\n"
    << "compiler: g++ " << __VERSION__ << "\n"
    << "flags: " << RIGID_CXX_FLAGS << "\n"
    << "date: " << date << "\n"
    << "mode: " << (quick ? "quick" : "full") << "\n"
    << "bodies per cost run: " << kCopies << ", cost = thread CPU time, median of "
    << (quick ? 1 : 3) << "\n";
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  std::string out = "bench/results/work_precision.csv";
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--quick") {
      quick = true;
    } else if (a == "--out" && i + 1 < argc) {
      out = argv[++i];
    } else if (a == "--help" || a == "-h") {
      std::cout << "usage: work_precision [--quick] [--out FILE.csv]\n";
      return 0;
    } else {
      std::cerr << "work_precision: unknown argument '" << a << "' (try --help)\n";
      return 2;
    }
  }
  const std::vector<double> steps =
      quick ? std::vector<double>{1.0 / 60, 1.0 / 240, 1.0 / 1000, 1.0 / 4000}
            : std::vector<double>{1.0 / 60,   1.0 / 120,  1.0 / 240,  1.0 / 500,
                                  1.0 / 1000, 1.0 / 2000, 1.0 / 5000, 1.0 / 10000};
  const std::string tmp = out + ".tmp";
  std::ofstream csv(tmp);
  if (!csv) {
    std::cerr << "work_precision: cannot write '" << tmp << "'\n";
    return 1;
  }
  csv << "case,integrator,dt,steps,err_orientation_rad,err_angular_velocity,err_position_m,"
         "energy_drift_rel,momentum_drift_rel,ns_per_body_step,cpu_ns_per_sim_second,reference\n";
  csv.precision(6);
  for (const Case& c : hard_cases()) {
    ref::RefState reference;
    reference.v = to_ld(c.body.v_WBo);
    reference.w = to_ld(c.body.w_WB);
    std::string reference_name = "closed form";
    if (c.torque_free) {
      // Degree 24 in quad precision, >= 200 steps per second: truncation < 1e-30.
      const double I[3] = {c.body.I_B(0, 0), c.body.I_B(1, 1), c.body.I_B(2, 2)};
      const double w0[3] = {c.body.w_WB.x(), c.body.w_WB.y(), c.body.w_WB.z()};
      long double q[4], w[3];
      const long n = std::lround(200 * c.duration * std::max(1.0, c.body.w_WB.norm() / 5.0));
      std::cerr << "[work_precision] " << c.name << ": reference (quad-precision Taylor, " << n
                << " steps)\n";
      ref::taylor_free_run(I, w0, c.duration, n, 24, q, w);
      reference.q = ref::Q4(q[0], q[1], q[2], q[3]);
      reference.w = ref::V3(w[0], w[1], w[2]);
      reference_name = "quad-precision Taylor series of degree 24";
    } else if (!c.closed_form_drag) {
      const long n = quick ? c.reference_steps / 4 : c.reference_steps;
      std::cerr << "[work_precision] " << c.name << ": reference (" << n
                << " long-double RK4 steps)\n";
      ref::ref_run(c.oracle, reference, c.duration, n);
      reference_name = "long-double RK4 at " + std::to_string(n) + " steps";
    }
    for (const auto& info : rigid::physics::all_integrators()) {
      for (double dt : steps) {
        const int repeats = quick ? 1 : 3;
        const Row r = run(c, std::string(info.name), dt, reference, repeats);
        csv << c.name << ',' << info.name << ',' << dt << ',' << std::lround(c.duration / dt) << ','
            << r.err_q << ',' << r.err_w << ',' << r.err_x << ',' << r.energy << ',' << r.momentum
            << ',' << r.ns_per_body_step << ',' << r.ns_per_body_step / dt << ',' << reference_name
            << '\n';
      }
      std::cerr << "[work_precision] " << c.name << " / " << info.name << " done\n";
    }
  }
  csv.close();
  if (std::rename(tmp.c_str(), out.c_str()) != 0) {
    std::cerr << "work_precision: cannot rename '" << tmp << "' to '" << out << "'\n";
    return 1;
  }
  write_meta(out + ".meta", quick);
  std::cerr << "[work_precision] wrote " << out << " and " << out << ".meta\n";
  return 0;
}
