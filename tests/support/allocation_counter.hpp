// Counts heap allocations in a test binary (every form of operator new is replaced in
// allocation_counter.cpp: plain, array, aligned, nothrow), so that a test can assert that some
// code allocates nothing: on any thread (allocation_count), or only on the threads that count
// (a CountingThread alive on them: the loop thread's own allocations, not the test's).
#pragma once

namespace rigid::test {

// Allocations made by operator new (any form), on any thread, since the program started.
long allocation_count();

// Allocations made on a thread while a CountingThread lived on it, since the last reset.
long counted_allocations();
void reset_counted_allocations();

// While alive, this thread's allocations are counted in counted_allocations().
class CountingThread {
 public:
  CountingThread();
  ~CountingThread();
  CountingThread(const CountingThread&) = delete;
  CountingThread& operator=(const CountingThread&) = delete;
};

}  // namespace rigid::test
