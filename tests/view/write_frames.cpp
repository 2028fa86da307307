// For protocol_test.mjs: state frames made by rigid-view's own encoder (protocol.cpp) from known
// states, printed as JSON with those states, so that the page's decoder (clients/view/web/
// protocol.js) is checked against what rigid-view really sends. Cases: a whole frame in f64, a
// whole frame in f32 (more than kExactStateMaxBodies bodies), a pose frame with watched bodies
// (one of them not in the state), a pose frame with no drift at all. Also the limits the page
// takes from protocol.hpp, as compiled here.
// usage: view_write_frames > frames.json
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

#include "protocol.hpp"

namespace {

using namespace rigid;
using namespace rigid::view;

std::string base64(const std::string& bytes) {
  static constexpr char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    std::uint32_t v = static_cast<std::uint8_t>(bytes[i]) << 16;
    if (i + 1 < bytes.size()) v |= static_cast<std::uint8_t>(bytes[i + 1]) << 8;
    if (i + 2 < bytes.size()) v |= static_cast<std::uint8_t>(bytes[i + 2]);
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += i + 1 < bytes.size() ? kAlphabet[(v >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? kAlphabet[v & 63] : '=';
  }
  return out;
}

// A JSON string (the command texts have no control characters).
std::string quoted(std::string_view text) {
  std::string out = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + '"';
}

template <typename T>
std::string list(const std::vector<T>& v) {
  std::string out = "[";
  char b[40];
  for (std::size_t i = 0; i < v.size(); ++i) {
    std::snprintf(b, sizeof b, "%.17g", static_cast<double>(v[i]));
    out += (i ? "," : "") + std::string(b);
  }
  return out + "]";
}

// n bodies with distinct ids (not their slots) and values no float32 holds exactly.
StateFrame state_of(std::size_t n) {
  StateFrame s;
  s.tick = 123'456'789'012;  // beyond 32 bits
  s.sim_time = 617.2500000000001;
  s.stamp_ns = 1'733'600'000'123'456'789;  // beyond 2^53: exact only as a BigInt
  for (std::size_t i = 0; i < n; ++i) {
    const double x = static_cast<double>(i);
    s.ids.push_back(static_cast<std::int32_t>(7 * i + 3));
    for (int k = 0; k < 3; ++k) {
      s.position.push_back(0.1 * x + 1e-9 * k - 2);
      s.linear_velocity.push_back(std::sin(x + k) / 3);
      s.angular_velocity.push_back(std::cos(x - k) * 7.000000001);
    }
    const double c = std::cos(0.01 * x), sn = std::sin(0.01 * x);
    for (const double q : {c, sn / std::sqrt(3.0), -sn / std::sqrt(3.0), sn / std::sqrt(3.0)})
      s.orientation.push_back(q);
  }
  return s;
}

std::vector<float> drifts(std::size_t n, float scale) {
  std::vector<float> d;
  for (std::size_t i = 0; i < n; ++i)
    d.push_back(scale * static_cast<float>((i * 37) % 101) * 1e-9f);
  return d;
}

void print_case(bool first, const char* name, const std::string& frame, const StateFrame& s,
                std::uint32_t generation, const std::vector<float>& energy,
                const std::vector<float>& momentum, const std::vector<std::int32_t>& watched) {
  std::printf(
      "%s{\"name\":\"%s\",\"frame\":\"%s\",\"generation\":%u,\"tick\":%lld,\"sim_time\":%.17g,"
      "\"stamp_ns\":\"%lld\",\"ids\":%s,\"position\":%s,\"orientation\":%s,"
      "\"linear_velocity\":%s,\"angular_velocity\":%s,\"energy_drift\":%s,"
      "\"momentum_drift\":%s,\"watched\":%s}\n",
      first ? "" : ",", name, base64(frame).c_str(), generation, static_cast<long long>(s.tick),
      s.sim_time, static_cast<long long>(s.stamp_ns), list(s.ids).c_str(), list(s.position).c_str(),
      list(s.orientation).c_str(), list(s.linear_velocity).c_str(),
      list(s.angular_velocity).c_str(), list(energy).c_str(), list(momentum).c_str(),
      list(watched).c_str());
}

}  // namespace

int main() {
  std::printf(
      "{\"limits\":{\"kMaxSteps\":%lld,\"kMaxWrenchesShown\":%zu,\"kWatchLifetime\":%.17g,"
      "\"kAckCommand\":%s},\n",
      static_cast<long long>(kMaxSteps), kMaxWrenchesShown, kWatchLifetime,
      quoted(kAckCommand).c_str());
  std::printf("\"cases\":[\n");
  {
    const StateFrame s = state_of(3);
    const std::vector<float> e{1e-12f, 2.5f, 0}, m{0.25f, 3e-9f, 7};
    print_case(true, "whole f64", encode_state(s, 5, e, m), s, 5, e, m, {});
  }
  {
    const std::size_t n = kExactStateMaxBodies + 1;
    const StateFrame s = state_of(n);
    const std::vector<float> e = drifts(n, 1), m = drifts(n, 3);
    print_case(false, "whole f32", encode_state(s, 6, e, m), s, 6, e, m, {});
  }
  {
    const std::size_t n = 300;
    const StateFrame s = state_of(n);
    const std::vector<float> e = drifts(n, 2), m = drifts(n, 5);
    const std::vector<std::int32_t> watched{s.ids[5], 999'999, s.ids[0]};
    print_case(false, "pose, watched", encode_pose_state(s, 7, e, m, watched), s, 7, e, m, watched);
  }
  {
    const StateFrame s = state_of(4);
    const std::vector<float> none(4, 0.0f);
    print_case(false, "pose, no drift", encode_pose_state(s, 8, none, none, {}), s, 8, none, none,
               {});
  }
  std::printf("]}\n");
  return 0;
}
