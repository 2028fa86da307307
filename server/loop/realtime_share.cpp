#include "loop/realtime_share.hpp"

namespace rigid::loop {

RealtimeShare::RealtimeShare(double limit, double resume, std::int64_t window_ns)
    : limit_(limit), resume_(resume), window_ns_(window_ns) {}

RealtimeShare::Change RealtimeShare::update(std::int64_t thread_cpu_ns, std::int64_t now_ns) {
  if (!started_ || thread_cpu_ns < cpu0_ || now_ns < wall0_) {
    started_ = true;
    cpu0_ = thread_cpu_ns;
    wall0_ = now_ns;
    return Change::kNone;
  }
  const std::int64_t wall = now_ns - wall0_;
  if (wall < window_ns_) return Change::kNone;
  last_share_ = static_cast<double>(thread_cpu_ns - cpu0_) / static_cast<double>(wall);
  cpu0_ = thread_cpu_ns;
  wall0_ = now_ns;
  if (!down_ && last_share_ > limit_) {
    down_ = true;
    return Change::kStepDown;
  }
  if (down_ && last_share_ < resume_) {
    down_ = false;
    return Change::kStepUp;
  }
  return Change::kNone;
}

}  // namespace rigid::loop
