// One of step_bench's worlds stepped a fixed number of times: a deterministic run whose
// instruction count (valgrind --tool=callgrind, counting inside World::step only) compares two
// builds where wall time on a shared machine cannot tell 1% apart.
//
//   valgrind --tool=callgrind --collect-atstart=no --toggle-collect='*World::step(long)'
//       build/bench/step_run racket hybrid4 1000 20
//   (one command line; prints its Ir, "Collected", on stderr)
//
// Cases: racket, sphere, top, point, thruster, torqued_top, torqued_sphere, lever_top
// (step_worlds.hpp).
// Under valgrind the lanes kernels run 4 wide (it has no AVX-512).
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "step_worlds.hpp"

int main(int argc, char** argv) {
  const auto c = argc == 5 ? rigid::bench::find_step_case(argv[1]) : std::nullopt;
  const int n = argc == 5 ? std::atoi(argv[3]) : 0;
  const long steps = argc == 5 ? std::atol(argv[4]) : 0;
  if (!c || n < 1 || steps < 1) {
    std::fprintf(stderr, "usage: step_run CASE INTEGRATOR BODIES STEPS\n");
    return 2;
  }
  rigid::physics::World w(rigid::bench::make_step_world(*c, n, argv[2]));
  w.step(2);  // the first steps make the caches
  w.step(steps);
  std::vector<double> p(3 * n), q(4 * n), v(3 * n), o(3 * n);
  w.write_states({p.data(), q.data(), v.data(), o.data()});
  std::printf("%.17g\n", p[0]);
  return 0;
}
