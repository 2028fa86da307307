#include "hard_cases.hpp"

#include <sys/utsname.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>

namespace rigid::bench {

namespace {

Vec3 to_double(const ref::V3& v) {
  return Vec3(double(v.x()), double(v.y()), double(v.z()));
}
Quat to_double(const ref::Q4& q) {
  return Quat(double(q.w()), double(q.x()), double(q.y()), double(q.z())).normalized();
}
ref::V3 to_ld(const Vec3& v) {
  return ref::V3(v.x(), v.y(), v.z());
}

double angle_between(const Quat& a, const Quat& b) {
  const Quat d = a.conjugate() * b;
  return 2.0 * std::atan2(d.vec().norm(), std::abs(d.w()));
}

BodySpec make_body(const Vec3& I, const Vec3& w0) {
  BodySpec b;
  b.name = "b";
  b.mass = 1.0;
  b.I_B = I.asDiagonal();
  b.w_WB = w0;
  b.use_gravity = false;
  return b;
}

// The closed form of v' = g - (c/m) v from v0, and its position.
Vec3 drag_position(const Case& c, const Vec3& g, double t) {
  const double k = c.body.linear_drag / c.body.mass, e = std::exp(-k * t);
  const Vec3 vinf = g / k;
  return vinf * t + (c.body.v_WBo - vinf) * (1 - e) / k;
}

}  // namespace

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

std::vector<double> sweep_steps(bool quick) {
  if (quick) return {1.0 / 60, 1.0 / 240, 1.0 / 1000, 1.0 / 4000};
  return {1.0 / 60,   1.0 / 120,  1.0 / 240,  1.0 / 500,
          1.0 / 1000, 1.0 / 2000, 1.0 / 5000, 1.0 / 10000};
}

std::vector<double> our_sweep_steps(bool quick) {
  std::vector<double> steps{1.0 / 10, 1.0 / 30};
  if (!quick) steps.insert(steps.begin() + 1, 1.0 / 20);
  for (double dt : sweep_steps(quick))
    steps.push_back(dt);
  return steps;
}

Vec3 gravity_of(const Case& c) {
  return c.body.use_gravity ? Vec3(0, 0, -9.81) : Vec3::Zero();
}

physics::WorldSpec world_spec(const Case& c, const std::string& integrator, double dt, int copies) {
  physics::WorldSpec ws;
  ws.dt = dt;
  ws.integrator = integrator;
  ws.g_W = gravity_of(c);
  for (int k = 0; k < copies; ++k) {
    BodySpec b = c.body;
    b.name = "b" + std::to_string(k);
    ws.bodies.push_back(b);
    for (LoadSpec l : c.loads) {
      l.body = k;
      ws.loads.push_back(l);
    }
  }
  return ws;
}

namespace {

Reference compute_reference_now(const Case& c, bool quick) {
  Reference r;
  r.state.v = to_ld(c.body.v_WBo);
  r.state.w = to_ld(c.body.w_WB);
  r.name = "closed form";
  if (c.torque_free) {
    // Degree 24 in quad precision, >= 200 steps per second: truncation < 1e-30.
    const double I[3] = {c.body.I_B(0, 0), c.body.I_B(1, 1), c.body.I_B(2, 2)};
    const double w0[3] = {c.body.w_WB.x(), c.body.w_WB.y(), c.body.w_WB.z()};
    long double q[4], w[3];
    const long n = std::lround(200 * c.duration * std::max(1.0, c.body.w_WB.norm() / 5.0));
    std::cerr << "[hard_cases] " << c.name << ": reference (quad-precision Taylor, " << n
              << " steps)\n";
    ref::taylor_free_run(I, w0, c.duration, n, 24, q, w);
    r.state.q = ref::Q4(q[0], q[1], q[2], q[3]);
    r.state.w = ref::V3(w[0], w[1], w[2]);
    r.name = "quad-precision Taylor series of degree 24";
  } else if (!c.closed_form_drag) {
    const long n = quick ? c.reference_steps / 4 : c.reference_steps;
    std::cerr << "[hard_cases] " << c.name << ": reference (" << n << " long-double RK4 steps)\n";
    ref::ref_run(c.oracle, r.state, c.duration, n);
    r.name = "long-double RK4 at " + std::to_string(n) + " steps";
  }
  return r;
}

// A cached reference: "key|x v q w (13 long doubles)|name", one a line.
std::string cache_key(const Case& c, bool quick) {
  return c.name + "/" + c.description + "/" + (quick ? "quick" : "full");
}

bool read_cached(const std::string& path, const std::string& key, Reference& r) {
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) {
    const auto a = line.find('|'), b = line.rfind('|');
    if (a == std::string::npos || b == a || line.substr(0, a) != key) continue;
    std::istringstream values(line.substr(a + 1, b - a - 1));
    long double v[13];
    for (long double& x : v)
      values >> x;
    if (!values) continue;
    r.state.x = ref::V3(v[0], v[1], v[2]);
    r.state.v = ref::V3(v[3], v[4], v[5]);
    r.state.q = ref::Q4(v[6], v[7], v[8], v[9]);
    r.state.w = ref::V3(v[10], v[11], v[12]);
    r.name = line.substr(b + 1);
    return true;
  }
  return false;
}

void write_cached(const std::string& path, const std::string& key, const Reference& r) {
  std::ofstream out(path, std::ios::app);
  out << key << '|' << std::setprecision(21);
  const ref::RefState& s = r.state;
  for (long double x : {s.x.x(), s.x.y(), s.x.z(), s.v.x(), s.v.y(), s.v.z(), s.q.w(), s.q.x(),
                        s.q.y(), s.q.z(), s.w.x(), s.w.y(), s.w.z()})
    out << x << ' ';
  out << '|' << r.name << '\n';
}

}  // namespace

Reference compute_reference(const Case& c, bool quick, const std::string& cache) {
  Reference r;
  if (!cache.empty() && read_cached(cache, cache_key(c, quick), r)) return r;
  r = compute_reference_now(c, quick);
  if (!cache.empty()) write_cached(cache, cache_key(c, quick), r);
  return r;
}

Scorer::Scorer(const Case& c, const Reference& r, long steps)
    : case_(c), ref_(r), steps_(steps), every_(std::max(1L, steps / 200)) {}

double Scorer::energy(const BodyState& s) const {
  const double m = case_.body.mass;
  const Vec3 w_B = s.q_WB.conjugate() * s.w_WB;
  double e = 0.5 * m * s.v_WBo.squaredNorm() + 0.5 * w_B.dot(case_.body.I_B * w_B) -
             m * gravity_of(case_).dot(s.p_WBo);
  for (const LoadSpec& l : case_.loads) {  // potential of constant world forces at points
    if (l.frame == Frame::kWorld) e -= l.force.dot(s.p_WBo + s.q_WB * l.p_BoQ_B);
  }
  return e;
}

Vec3 Scorer::momentum(const BodyState& s) const {
  const Vec3 w_B = s.q_WB.conjugate() * s.w_WB;
  return s.q_WB * (case_.body.I_B * w_B);
}

void Scorer::observe(long step, double t, const BodyState& s) {
  if (failed_) return;
  if (!s.p_WBo.allFinite() || !s.q_WB.coeffs().allFinite() || !s.w_WB.allFinite()) {
    failed_ = true;
    return;
  }
  if (!started_) {
    // The invariants at t = 0, from the case's initial state.
    const BodyState s0{case_.body.p_WBo, case_.body.q_WB, case_.body.v_WBo, case_.body.w_WB};
    E0_ = energy(s0);
    L0_ = momentum(s0);
    started_ = true;
  }
  if (case_.closed_form_drag) {
    worst_x_ = std::max(worst_x_, (s.p_WBo - drag_position(case_, gravity_of(case_), t)).norm());
  }
  if (case_.conservative && (step % every_ == 0 || step == steps_)) {
    worst_E_ = std::max(worst_E_, std::abs(energy(s) - E0_) / std::abs(E0_));
    if (case_.loads.empty()) {
      worst_L_ = std::max(worst_L_, (momentum(s) - L0_).norm() / L0_.norm());
    }
  }
}

Row Scorer::result(const BodyState& s) const {
  Row row;
  if (failed_) {
    row.err_q = row.err_w = row.err_x = INFINITY;
    return row;
  }
  if (case_.closed_form_drag) {
    row.err_x = worst_x_;
  } else {
    row.err_q = angle_between(s.q_WB, to_double(ref_.state.q));
    row.err_w = (s.w_WB - to_double(ref_.state.q) * to_double(ref_.state.w)).norm();
    row.err_x = (s.p_WBo - to_double(ref_.state.x)).norm();
  }
  if (case_.conservative) {
    row.energy = worst_E_;
    if (case_.loads.empty()) row.momentum = worst_L_;
  }
  return row;
}

bool blown_up(const BodyState& s, const BodyState& prev, double dt) {
  constexpr double kBound = 1e10;
  const auto bad = [](const Vec3& v) { return !(v.cwiseAbs().maxCoeff() <= kBound); };
  return !s.p_WBo.allFinite() || !s.v_WBo.allFinite() || !s.w_WB.allFinite() || bad(s.p_WBo) ||
         bad(s.v_WBo) || bad(s.w_WB) || bad((s.v_WBo - prev.v_WBo) / dt) ||
         bad((s.w_WB - prev.w_WB) / dt);
}

BodyState nan_state() {
  BodyState s;
  s.p_WBo.setConstant(NAN);
  return s;
}

double thread_cpu_ns() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return 1e9 * static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_nsec);
}

void write_csv_header(std::ostream& os) {
  os << "case,integrator,dt,steps,err_orientation_rad,err_angular_velocity,err_position_m,"
        "energy_drift_rel,momentum_drift_rel,ns_per_body_step,cpu_ns_per_sim_second,reference\n";
}

void write_csv_row(std::ostream& os, const Case& c, const std::string& integrator, double dt,
                   const Row& r, double ns, const std::string& reference) {
  os.precision(6);
  os << c.name << ',' << integrator << ',' << dt << ',' << std::lround(c.duration / dt) << ','
     << r.err_q << ',' << r.err_w << ',' << r.err_x << ',' << r.energy << ',' << r.momentum << ','
     << ns << ',' << ns / dt << ',' << reference << '\n';
}

// What the figures must say about where they come from: machine, compiler, flags, date.
void write_meta(const std::string& path, bool quick, int copies, int repeats,
                const std::string& extra) {
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
    << "mode: " << (quick ? "quick" : "full") << "\n";
  if (copies > 0) {
    m << "bodies per cost run: " << copies << ", cost = thread CPU time, median of " << repeats
      << "\n";
  }
  m << extra;
}

}  // namespace rigid::bench
