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
#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "step_worlds.hpp"

namespace {

// The whole of `text` as an integer in [lo, hi], else nullopt.
std::optional<long> integer_in(const char* text, long lo, long hi) {
  const std::string_view t(text);
  long v = 0;
  const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  if (ec != std::errc() || end != t.data() + t.size() || v < lo || v > hi) return std::nullopt;
  return v;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 5) {
    std::fprintf(stderr, "usage: step_run CASE INTEGRATOR BODIES STEPS\n");
    return 2;
  }
  const auto c = rigid::bench::find_step_case(argv[1]);
  const auto n = integer_in(argv[3], 1, 10'000'000);
  const auto steps = integer_in(argv[4], 1, 1'000'000'000);
  if (!c) return std::fprintf(stderr, "step_run: CASE: unknown case '%s'\n", argv[1]), 2;
  if (!n)
    return std::fprintf(stderr, "step_run: BODIES: expected 1 .. 10^7, got '%s'\n", argv[3]), 2;
  if (!steps)
    return std::fprintf(stderr, "step_run: STEPS: expected 1 .. 10^9, got '%s'\n", argv[4]), 2;
  try {
    rigid::physics::World w(rigid::bench::make_step_world(*c, static_cast<int>(*n), argv[2]));
    w.step(2);  // the first steps make the caches
    w.step(*steps);
    const auto m = static_cast<std::size_t>(*n);
    std::vector<double> p(3 * m), q(4 * m), v(3 * m), o(3 * m);
    w.write_states({p.data(), q.data(), v.data(), o.data()});
    std::printf("%.17g\n", p[0]);
  } catch (const std::exception& e) {  // an unknown INTEGRATOR: the World names it
    std::fprintf(stderr, "step_run: %s\n", e.what());
    return 2;
  }
  return 0;
}
