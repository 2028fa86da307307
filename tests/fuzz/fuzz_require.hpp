// The fuzzers' assertion: a promise of our code that an input broke. It aborts, so libFuzzer stops
// and saves the input as a crash, like any sanitizer finding (assert() is compiled out at
// -DNDEBUG).
#pragma once

#include <cstdio>
#include <cstdlib>

namespace rigid::fuzz {

inline void require(bool holds, const char* promise) {
  if (holds) return;
  std::fprintf(stderr, "broken promise: %s\n", promise);
  std::abort();
}

}  // namespace rigid::fuzz
