#include "common/state_hash.hpp"

#include <bit>
#include <vector>

namespace rigid::common {
namespace {

constexpr std::uint64_t kMultiplier = 0x9E3779B97F4A7C15ULL;  // odd: multiplying is a bijection

std::uint64_t fold(std::uint64_t h, std::uint64_t word) {
  return std::rotl((h ^ word) * kMultiplier, 27);
}

std::uint64_t fold_all(std::uint64_t h, const std::vector<double>& values) {
  for (const double v : values)
    h = fold(h, std::bit_cast<std::uint64_t>(v));
  return h;
}

// splitmix64's finaliser, so that nearby inputs give unrelated-looking outputs.
std::uint64_t finish(std::uint64_t x) {
  x ^= x >> 30;
  x *= 0xbf58476d1ce4e5b9ULL;
  x ^= x >> 27;
  x *= 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

template <class T>
std::uint64_t fold_ints(std::uint64_t h, const std::vector<T>& values) {
  for (const T v : values)
    h = fold(h, static_cast<std::uint64_t>(static_cast<std::int64_t>(v)));
  return h;
}

}  // namespace

std::uint64_t state_hash(const rigid::StateFrame& frame) {
  std::uint64_t h = fold(0x7269676964ULL, static_cast<std::uint64_t>(frame.tick));  // "rigid"
  h = fold(h, frame.ids.size());
  h = fold_all(h, frame.position);
  h = fold_all(h, frame.orientation);
  h = fold_all(h, frame.linear_velocity);
  h = fold_all(h, frame.angular_velocity);
  return finish(h);
}

std::uint64_t contact_hash(const rigid::ContactEvents& events) {
  std::uint64_t h =
      fold(0x636f6e74616374ULL, static_cast<std::uint64_t>(events.tick));  // "contact"
  h = fold(h, std::bit_cast<std::uint64_t>(events.sim_time));
  h = fold(h, events.kinds.size());
  h = fold_ints(h, events.kinds);
  h = fold_ints(h, events.bodies);
  h = fold_ints(h, events.parts);
  h = fold_all(h, events.times);
  h = fold_all(h, events.position);
  h = fold_all(h, events.normal);
  h = fold_all(h, events.impulse);
  return finish(h);
}

}  // namespace rigid::common
