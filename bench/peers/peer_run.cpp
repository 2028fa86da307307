#include "peer_run.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace rigid::bench::peers {

Row accuracy_run(const PeerEngine& engine, const Case& c, const std::string& mode, double dt,
                 const Reference& reference, int copies) {
  const long n = std::lround(c.duration / dt);
  const auto world = engine.make_world(c, mode, dt, copies);
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
                int repeats, int copies) {
  const long n = std::lround(c.duration / dt);
  std::vector<double> t;
  for (int r = 0; r < repeats; ++r) {
    const auto world = engine.make_world(c, mode, dt, copies);  // built outside the timing
    const double t0 = thread_cpu_ns();
    for (long i = 0; i < n; ++i)
      world->step();
    t.push_back((thread_cpu_ns() - t0) / (static_cast<double>(n) * copies));
  }
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

}  // namespace rigid::bench::peers
