#include "peer_run.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace rigid::bench::peers {

namespace {

// A run counts as blown up where MuJoCo would reset it, by MuJoCo's own bound on a sane value
// (mjMAXVAL = 1e10) on positions, velocities and accelerations (here the change of velocity over
// the step just taken, per dt), applied to every peer alike: an explicit drag at c dt / m > 2
// then reads as a blow-up in Bullet and ODE at the step where MuJoCo resets, rather than as a
// finite but meaningless error that grows ~|1 - c dt / m|^n.
constexpr double kBlownUp = 1e10;

bool blown_up(const BodyState& s, const BodyState& prev, double dt) {
  const auto bad = [](const Vec3& v) { return !(v.cwiseAbs().maxCoeff() <= kBlownUp); };
  return !s.p_WBo.allFinite() || !s.v_WBo.allFinite() || !s.w_WB.allFinite() || bad(s.p_WBo) ||
         bad(s.v_WBo) || bad(s.w_WB) || bad((s.v_WBo - prev.v_WBo) / dt) ||
         bad((s.w_WB - prev.w_WB) / dt);
}

BodyState nan_state() {
  BodyState s;
  s.p_WBo.setConstant(std::numeric_limits<double>::quiet_NaN());
  return s;
}

}  // namespace

Row accuracy_run(const PeerEngine& engine, const Case& c, const std::string& mode, double dt,
                 const Reference& reference) {
  const long n = std::lround(c.duration / dt);
  const auto world = engine.make_world(c, mode, dt, kCopies);
  Scorer score(c, reference, n);
  BodyState prev = world->state(0), s = prev;
  for (long i = 1; i <= n && !score.failed(); ++i) {
    world->step();
    s = world->state(0);
    if (blown_up(s, prev, dt)) s = nan_state();  // the Scorer then reports infinite errors
    // i * dt rather than an engine's accumulated clock: every engine is scored at the same times.
    score.observe(i, static_cast<double>(i) * dt, s);
    prev = s;
  }
  return score.result(s);
}

double cost_run(const PeerEngine& engine, const Case& c, const std::string& mode, double dt,
                int repeats) {
  const long n = std::lround(c.duration / dt);
  std::vector<double> t;
  for (int r = 0; r < repeats; ++r) {
    const auto world = engine.make_world(c, mode, dt, kCopies);  // built outside the timing
    const double t0 = thread_cpu_ns();
    for (long i = 0; i < n; ++i)
      world->step();
    t.push_back((thread_cpu_ns() - t0) / (static_cast<double>(n) * kCopies));
  }
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

}  // namespace rigid::bench::peers
