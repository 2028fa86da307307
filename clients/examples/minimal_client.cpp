// A minimal rigid client: subscribe to the state, push one force, print what it does.
// Start rigidd first (scripts/dev run), then run this; add --lcm to use LCM instead of DDS.
#include <atomic>
#include <chrono>
#include <cstdio>
#include <memory>
#include <random>
#include <string_view>
#include <thread>

#include "transport/dds/dds_transport.hpp"
#include "transport/lcm/lcm_transport.hpp"

using namespace rigid::transport;

// Called on the transport's thread for every state rigidd publishes.
struct Printer : Receiver {
  std::atomic<long> states{0};
  void on_state(const StateFrame& s) override {
    if (states++ % 20 == 0 && s.body_count() > 0) {  // body 0: position and velocity
      std::printf("tick %6lld  x %8.4f  vx %8.4f m/s\n", static_cast<long long>(s.tick),
                  s.position[0], s.linear_velocity[0]);
    }
  }
};

int main(int argc, char** argv) {
  const bool lcm = argc > 1 && std::string_view(argv[1]) == "--lcm";
  Printer printer;
  std::unique_ptr<Transport> bus;
  if (lcm) {
    lcm::Options o;
    o.role = Role::kClient;
    bus = lcm::make_transport(o, printer);
  } else {
    dds::Options o;
    o.role = Role::kClient;
    bus = dds::make_transport(o, printer);
  }
  // Wait for the first state: on DDS, a message sent before discovery would be lost.
  for (int i = 0; printer.states == 0; ++i) {
    if (i == 500) {
      std::puts("no state from rigidd within 5 s (is it running?)");
      return 1;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }

  WrenchCommand push;
  push.source = std::random_device{}();  // this run's id (rigidd remembers each id's last seq)
  push.seq = 1;                          // increases with each command from this source
  push.body_id = 0;                      // the first body of the scene (or set body_name)
  push.force = {10, 0, 0};               // 10 N along the world's x...
  push.ttl = 0.5;                        // ...for half a second
  bus->publish(push);

  std::this_thread::sleep_for(std::chrono::seconds(2));
}
