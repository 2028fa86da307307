// A minimal rigid client: subscribe to the state, push one force, print what it does.
// Start rigidd first (scripts/dev run), then run this; add --lcm to use LCM instead of DDS.
// Build it against the installed SDK: find_package(rigid) and link rigid::client, or
// c++ -std=c++20 minimal_client.cpp $(pkg-config --cflags --libs rigid).
#include <atomic>
#include <chrono>
#include <cstdio>
#include <rigid/client.hpp>
#include <string>
#include <string_view>
#include <thread>

using namespace std::chrono_literals;

int main(int argc, char** argv) {
  rigid::client::BusOptions bus;  // DDS domain 0, no prefix: what rigidd uses by default
  for (int i = 1; i < argc; ++i) {
    const std::string_view arg = argv[i];
    if (arg == "--lcm") {
      bus.bus = rigid::Bus::kLcm;
    } else if (arg == "--help") {
      std::puts(
          "usage: rigid_minimal_client [--lcm]: prints body 0 of rigidd's state and "
          "pushes it with 10 N along x for 0.5 s");
      return 0;
    } else {
      std::fprintf(stderr, "rigid_minimal_client: unknown argument '%s' (try --help)\n", argv[i]);
      return 2;
    }
  }
  try {
    rigid::client::Session session(bus);
    // Called on the bus's thread for every state rigidd publishes.
    std::atomic<long> states{0};
    session.on_each_state([&](const rigid::StateFrame& s) {
      if (states++ % 20 == 0 && s.body_count() > 0) {  // body 0: position and velocity
        std::printf("tick %6lld  x %8.4f  vx %8.4f m/s\n", static_cast<long long>(s.tick),
                    s.position[0], s.linear_velocity[0]);
      }
    });
    if (!session.wait_server(5s)) {
      std::puts("no state from rigidd within 5 s (is it running?)");
      return 1;
    }
    rigid::WrenchCommand push;
    push.body_id = 0;         // the first body of the scene (or set body_name)
    push.force = {10, 0, 0};  // 10 N along the world's x...
    push.ttl = 0.5;           // ...for half a second
    std::string refused;
    if (!session.push(push, 5s, &refused)) {  // source and seq are the session's
      std::printf("push refused: %s\n", refused.empty() ? "no answer" : refused.c_str());
      return 1;
    }
    std::this_thread::sleep_for(2s);
    session.on_each_state({});  // before `states` goes away
  } catch (const rigid::client::BusError& e) {
    std::fprintf(stderr, "rigid_minimal_client: %s\n", e.what());
    return 1;
  }
}
