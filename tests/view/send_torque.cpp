// view_send_torque: sends rigidd one pure-torque wrench (no force) on DDS and waits until it is
// accepted, for browser_test.mjs (rigidctl push sends forces only). Prints "accepted at tick N".
// usage: view_send_torque PREFIX BODY TX,TY,TZ world|body TTL
// Exit status: 0 accepted, 1 refused or no answer within 10 s (rigidd's reason on stderr), 2 a bad
// argument (one line naming it).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <iostream>
#include <string>
#include <string_view>
#include <vector>

#include "rigid/client/session.hpp"

namespace {

using namespace std::chrono_literals;

// "x,y,z": three finite numbers.
bool parse_vec3(const std::string& text, rigid::Vec3& out) {
  double v[3];
  char tail = 0;
  if (std::sscanf(text.c_str(), "%lf,%lf,%lf%c", &v[0], &v[1], &v[2], &tail) != 3) return false;
  for (int i = 0; i < 3; ++i) {
    if (!std::isfinite(v[i])) return false;
    out[static_cast<std::size_t>(i)] = v[i];
  }
  return true;
}

int usage_error(const std::string& what) {
  std::cerr << "view_send_torque: " << what
            << " (usage: view_send_torque PREFIX BODY TX,TY,TZ world|body TTL)\n";
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  if (args.size() != 5)
    return usage_error("expected 5 arguments, got " + std::to_string(args.size()));
  rigid::WrenchCommand w;
  w.body_name = args[1];
  if (w.body_name.empty() || w.body_name.size() > 256)
    return usage_error("BODY: expected a name of 1 to 256 characters");
  if (!parse_vec3(args[2], w.torque))
    return usage_error("torque: expected x,y,z, got '" + args[2] + "'");
  if (args[3] != "world" && args[3] != "body")
    return usage_error("frame: expected world or body, got '" + args[3] + "'");
  w.torque_frame = args[3] == "body" ? rigid::Frame::kBody : rigid::Frame::kWorld;
  char tail = 0;
  if (std::sscanf(args[4].c_str(), "%lf%c", &w.ttl, &tail) != 1 || !(w.ttl >= 0 && w.ttl <= 60))
    return usage_error("TTL: expected seconds in [0, 60], got '" + args[4] + "'");
  try {
    rigid::client::BusOptions bus;
    bus.bus = rigid::Bus::kDds;
    bus.prefix = args[0];
    rigid::client::Session session(bus);
    std::string refused;
    const auto accepted = session.push(w, 10s, &refused);
    if (!accepted) {
      std::cerr << "view_send_torque: " << (refused.empty() ? "no answer within 10 s" : refused)
                << '\n';
      return 1;
    }
    std::cout << "accepted at tick " << accepted->tick << std::endl;
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "view_send_torque: " << e.what() << '\n';
    return 1;
  }
}
