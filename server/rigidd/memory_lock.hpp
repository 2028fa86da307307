// Keeps rigidd's pages in RAM while it runs in realtime mode. A page the kernel drops (this
// project's test VM runs DAMON, which pages out cold memory; with swap, any page can go) is read
// back from disk the next time a thread touches it: a major fault, which stops that thread for as
// long as the read takes, be it the loop in the middle of a tick (bench/loop/loop_bench.cpp counts
// them per thread: one on the loop in a minute at 10^4 bodies). Real-time practice is to lock the
// process's memory (mlockall(2)); rigidd does so once started.
#pragma once

#include <string>

namespace rigid::rigidd {

// Locks every page rigidd has mapped now, each once it is in memory (MCL_CURRENT | MCL_ONFAULT:
// nothing is read in or allocated for the lock, and a mapping's pages never touched stay out).
// Not MCL_FUTURE: with it, any later allocation beyond RLIMIT_MEMLOCK would fail instead of being
// made. Call it after the loading memory was given back (malloc_trim): a locked page can no
// longer be. Returns the line for rigidd's log: what was locked, or why nothing was.
std::string lock_memory();

}  // namespace rigid::rigidd
