// A stand-in for rigidd with no physics and no hand-offs, run by `loop_bench echo`: the floor
// under the wrench-to-state latency that `loop_bench realtime` measures of rigidd. It serves the
// same topics with the same message sizes: a state of N bodies every publish_every ticks, and,
// right after a tick in which a wrench arrived, a state in which the pushed body's velocity
// changed. Its tick thread runs as rigidd's loop does (SCHED_FIFO when allowed, on the last CPU,
// sleeping to each tick's deadline with a 100 us final spin), but publishes from that thread
// itself: rigidd's command queue, step and publisher thread are what it leaves out. With at_once,
// it answers each wrench from the bus's receive thread as it arrives, without waiting for a tick:
// then the latency is the two trips over the bus alone, what no server can beat.
#pragma once

#include <string>
#include <vector>

#include "rigid/messages.hpp"

namespace rigid::bench {

struct EchoOptions {
  std::string prefix;  // the topics' prefix, as rigidd's --prefix
  std::vector<rigid::Bus> buses;
  int bodies = 1000;
  int rate_hz = 1000;
  int publish_every = 10;
  bool at_once = false;
};

// Serves until SIGTERM or SIGINT; returns the exit status (0, or 1 with a line on stderr).
int run_echo_server(const EchoOptions& options);

}  // namespace rigid::bench
