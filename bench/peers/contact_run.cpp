#include "contact_run.hpp"

#include <algorithm>
#include <cmath>

namespace rigid::bench::peers {

long contact_steps(const ContactCase& c, double dt) {
  return std::lround(c.duration / dt);
}

ContactRow contact_accuracy_run(const ContactEngine& engine, const ContactCase& c,
                                const std::string& mode, double dt) {
  const auto world = engine.make_world(c, mode, dt, 1, true);
  ContactScorer score(c, dt, engine.locates_events());
  const long n = contact_steps(c, dt);
  for (long i = 1; i <= n && !score.failed(); ++i) {
    world->step();
    score.observe(i, world->state(0), world->contact(0), world->events(0));
  }
  return score.result();
}

ContactCost contact_cost_run(const ContactEngine& engine, const ContactCase& c,
                             const std::string& mode, double dt, int copies, double min_ns) {
  const long n = contact_steps(c, dt), settle = std::min(n - 1, std::lround(kSettleTime / dt));
  double all = 0, settled = 0;  // CPU time (ns)
  long runs = 0;
  while (runs == 0 || all < min_ns) {
    const auto world = engine.make_world(c, mode, dt, copies, false);
    const double t0 = thread_cpu_ns();
    for (long i = 0; i < settle; ++i)
      world->step();
    const double t1 = thread_cpu_ns();
    for (long i = settle; i < n; ++i)
      world->step();
    const double t2 = thread_cpu_ns();
    all += t2 - t0;
    settled += t2 - t1;
    ++runs;
  }
  const double bodies = static_cast<double>(runs) * copies;
  return {all / (static_cast<double>(n) * bodies),
          settled / (static_cast<double>(n - settle) * bodies)};
}

}  // namespace rigid::bench::peers
