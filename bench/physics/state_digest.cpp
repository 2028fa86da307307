// Prints a digest of the states a World steps to, to compare two builds bit for bit: one line per
// integrator and phase with an FNV-1a hash of every body's state (state(id) and write_states), its
// energies and momenta, the guard's frozen bodies, large_rotation_steps and what prepare_step
// made. A restructuring that must change no result (the physics library's) shows the same lines
// before and after (the build before's output in old.txt, then `diff old.txt new.txt`), with the
// widest lanes kernel, the narrower ones and the scalar code (RIGID_LANES=4, 2, 1), on 1 and 2
// threads:
//
//   build/bench/state_digest > new.txt
//   RIGID_LANES=1 build/bench/state_digest --threads 2 > new-scalar-2.txt
//
// The scene has bodies of every kind a World tells apart (point masses, bodies with every rotation
// locked, kinematic bodies still and spinning, hinges about each world axis, isotropic,
// axisymmetric both ways and general bodies), with and without gravity, drags and locked
// translations, scene loads of every kind; between phases it applies and clears loads (bodies
// move between the quiet and the loaded runs), impulses, set_state, a copy and reset(); a last
// phase drives some bodies past the guard's bounds so that it freezes them.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "physics/world.hpp"

namespace {

using rigid::physics::BodySpec;
using rigid::physics::BodyState;
using rigid::physics::Frame;
using rigid::physics::LoadSpec;
using rigid::physics::Mat3;
using rigid::physics::Quat;
using rigid::physics::StateRows;
using rigid::physics::Vec3;
using rigid::physics::World;
using rigid::physics::WorldSpec;

struct Hash {
  std::uint64_t h = 1469598103934665603ull;
  void bytes(const void* p, std::size_t n) {
    const auto* c = static_cast<const unsigned char*>(p);
    for (std::size_t i = 0; i < n; ++i) {
      h ^= c[i];
      h *= 1099511628211ull;
    }
  }
  void d(double x) { bytes(&x, sizeof x); }
  void v(const Vec3& x) {
    for (int a = 0; a < 3; ++a)
      d(x[a]);
  }
  void q(const Quat& x) { d(x.w()), d(x.x()), d(x.y()), d(x.z()); }
  void i(std::int64_t x) { bytes(&x, sizeof x); }
};

// Body k of the scene: its kind cycles through kKinds.
constexpr int kKinds = 16;
BodySpec make_body(int k) {
  BodySpec b;
  b.name = "b" + std::to_string(k);
  const double e = 1e-3 * (k % 17);
  b.p_WBo = Vec3(0.1 * k, -0.05 * k, 1.0 + e);
  b.v_WBo = Vec3(0.3 - e, 0.2, 1.0 + e);
  b.w_WB = Vec3(0.4 + e, -2.0, 1.5 - e);
  b.q_WB = Quat(1.0, 0.1 * e, 0.2, -0.3 + e).normalized();
  b.mass = 1.0 + 0.25 * (k % 3);
  switch (k % kKinds) {
    case 0:
      b.has_inertia = false;  // a point mass
      break;
    case 1:
      b.freeze_rotation = {true, true, true};
      b.I_B = Vec3(1, 2, 3).asDiagonal();
      break;
    case 2:
      b.kinematic = true;
      b.w_WB.setZero();
      break;
    case 3:
      b.kinematic = true;
      b.I_B = Vec3(1, 2, 3).asDiagonal();
      break;
    case 4:
    case 5:
    case 6: {
      // A hinge about world axis k % 3, a general tensor.
      const int free = k % kKinds - 4;
      for (int a = 0; a < 3; ++a)
        b.freeze_rotation[a] = a != free;
      Mat3 I;
      I << 2.0, 0.1, 0.0, 0.1, 3.0, 0.2, 0.0, 0.2, 4.0;
      b.I_B = I;
      b.angular_drag = k % 2 == 0 ? 0.05 : 0.0;
      break;
    }
    case 7:
      b.I_B = Vec3(0.4, 0.4, 0.4).asDiagonal();
      break;
    case 8:
      b.I_B = Vec3(1, 1, 1.8).asDiagonal();  // oblate
      b.angular_drag = 0.02;
      break;
    case 9:
      b.I_B = Vec3(2, 2, 0.5).asDiagonal();  // prolate
      b.w_WB = Vec3(0.5, 0.2, 30.0 + e);
      break;
    case 10: {
      Mat3 I;
      I << 1.2, 0.05, 0.0, 0.05, 2.0, 0.1, 0.0, 0.1, 3.0;
      b.I_B = I;
      b.w_WB = Vec3(1e-3 + e, 5.0, 1e-3);  // about the middle axis: a flip
      break;
    }
    case 11:
      b.I_B = Vec3(0.5, 1.0, 1.3).asDiagonal();
      b.linear_drag = 0.3;
      b.freeze_translation = {false, true, false};
      break;
    case 12:
      b.I_B = Vec3(0.5, 1.0, 1.3).asDiagonal();
      b.use_gravity = false;
      b.w_WB = Vec3(k % 32 < 16 ? 300.0 : 4000.0, 1.0, -2.0);  // fast: libm branches, long steps
      break;
    case 13:
      b.I_B = Vec3(1, 1, 1.8).asDiagonal();
      b.freeze_translation = {true, true, false};
      b.linear_drag = 0.5;
      break;
    case 14:
      b.has_inertia = false;
      b.linear_drag = 0.2;
      break;
    case 15:
      b.I_B = Vec3(1, 2, 2).asDiagonal();
      b.use_gravity = false;
      b.angular_drag = 0.1;
      break;
  }
  return b;
}

WorldSpec make_scene(int n, const std::string& integrator, int threads) {
  WorldSpec ws;
  ws.dt = 1e-3;
  ws.integrator = integrator;
  ws.threads = threads;
  ws.g_W = Vec3(0.0, 0.5, -9.81);
  for (int k = 0; k < n; ++k)
    ws.bodies.push_back(make_body(k));
  // Scene loads of every kind on every fifth body, alike in runs (shared terms).
  for (int k = 0; k < n; k += 5) {
    LoadSpec l;
    l.body = k;
    switch (k / 5 % 5) {
      case 0:
        l.force = Vec3(0, 0, 4);
        l.p_BoQ_B = Vec3(0.4, 0.1, 0);
        l.frame = Frame::kBody;
        break;
      case 1:
        l.force = Vec3(1, 0, 0);
        l.p_BoQ_B = Vec3(0, 0.3, 0);
        break;
      case 2:
        l.torque = Vec3(0, 0.2, 0.1);
        l.torque_frame = Frame::kBody;
        break;
      case 3:
        l.torque = Vec3(0.1, 0, 0);
        break;
      case 4:
        l.force = Vec3(0, 2, 0);  // at the centre of mass, in W: stays quiet
        break;
    }
    ws.loads.push_back(l);
  }
  return ws;
}

void digest(const World& w, const char* integrator, const char* phase, int made) {
  Hash h;
  const int n = w.body_count();
  std::vector<double> p(3 * n), q(4 * n), v(3 * n), o(3 * n);
  w.write_states(StateRows{p.data(), q.data(), v.data(), o.data()});
  h.bytes(p.data(), p.size() * sizeof(double));
  h.bytes(q.data(), q.size() * sizeof(double));
  h.bytes(v.data(), v.size() * sizeof(double));
  h.bytes(o.data(), o.size() * sizeof(double));
  Hash s;
  for (int id = 0; id < n; ++id) {
    const BodyState st = w.state(id);
    s.v(st.p_WBo), s.q(st.q_WB), s.v(st.v_WBo), s.v(st.w_WB);
    s.d(w.kinetic_energy(id));
    s.v(w.angular_momentum_W(id));
    s.v(w.principal_moments(id));
    s.q(w.q_BP(id));
  }
  s.d(w.total_energy());
  for (const int id : w.frozen_bodies())
    s.i(id);
  std::printf(
      "%-16s %-10s t=%.6f steps=%lld large=%lld frozen=%zu made=%d states=%016llx "
      "rest=%016llx\n",
      integrator, phase, w.time(), static_cast<long long>(w.step_count()),
      static_cast<long long>(w.large_rotation_steps()), w.frozen_bodies().size(), made,
      static_cast<unsigned long long>(h.h), static_cast<unsigned long long>(s.h));
}

void run(const std::string& integrator, int n, int threads) {
  const char* name = integrator.c_str();
  World w(make_scene(n, integrator, threads));
  int made = w.prepare_step();
  digest(w, name, "built", made);
  w.step(50);
  digest(w, name, "free", 0);
  // Applied loads on a third of the bodies (some quiet ones become loaded), then cleared on half
  // of those (they go back), impulses here and there.
  for (int id = 0; id < n; id += 3) {
    w.add_force(id, Vec3(0.5, -0.2, 1.0), Vec3(0.1, 0.0, -0.2),
                id % 2 ? Frame::kBody : Frame::kWorld);
    if (id % 9 == 0) w.add_torque(id, Vec3(0.0, 0.3, -0.1), Frame::kBody);
    if (id % 4 == 0) w.add_force(id, Vec3(0.0, 0.0, 2.0), Vec3::Zero(), Frame::kWorld);
  }
  for (int id = 1; id < n; id += 7)
    w.apply_impulse(id, Vec3(0.2, 0.0, -0.1), Vec3(0.0, 0.1, 0.05),
                    id % 2 ? Frame::kBody : Frame::kWorld);
  w.step(40);
  digest(w, name, "loaded", 0);
  for (int id = 0; id < n; id += 6)
    w.clear_applied(id);
  for (int id = 2; id < n; id += 11) {
    BodyState st = w.state(id);
    st.w_WB = Vec3(0.3, -1.0 + 1e-3 * id, 2.0);
    st.v_WBo *= 0.5;
    w.set_state(id, st);
  }
  made = w.prepare_step();
  digest(w, name, "edited", made);
  w.step(70);
  digest(w, name, "stepped", 0);
  World copy = w;
  copy.step(10);
  w.clear_applied();
  w.step(10);
  digest(copy, name, "copy", 0);
  digest(w, name, "cleared", 0);
  w.reset();
  made = w.prepare_step();
  w.step(30);
  digest(w, name, "reset", made);
}

// The guard: explicit Euler past c dt / m = 2 diverges; the guard freezes those bodies.
void run_guard(int threads) {
  WorldSpec ws = make_scene(600, "notes_explicit_euler", threads);
  for (int k = 0; k < 600; k += 13)
    ws.bodies[k].linear_drag = 3000.0 * ws.bodies[k].mass;
  World w(ws);
  w.step(700);
  digest(w, "explicit_guard", "guarded", 0);
  w.apply_impulse(13, Vec3(1, 1, 1), Vec3::Zero(), Frame::kWorld);
  w.add_force(26, Vec3(1, 1, 1), Vec3::Zero(), Frame::kWorld);
  w.step(64);
  digest(w, "explicit_guard", "frozen", 0);
  w.reset();
  w.step(10);
  digest(w, "explicit_guard", "thawed", 0);
}

}  // namespace

int main(int argc, char** argv) {
  int threads = 1, n = 1100;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--threads") == 0 && i + 1 < argc) {
      threads = std::atoi(argv[++i]);
    } else if (std::strcmp(argv[i], "--bodies") == 0 && i + 1 < argc) {
      n = std::atoi(argv[++i]);
    } else {
      std::fprintf(stderr, "usage: state_digest [--threads N] [--bodies N]\n");
      return 2;
    }
  }
  for (const auto& info : rigid::physics::all_integrators())
    run(std::string(info.name), n, threads);
  run("hybrid4_suzuki", n, threads);
  run_guard(threads);
  return 0;
}
