#include "echo_server.hpp"

#include <pthread.h>
#include <sched.h>
#include <sys/prctl.h>

#include <csignal>
#include <cstdint>
#include <cstdio>
#include <ctime>
#include <exception>
#include <memory>
#include <mutex>

#include "transport/dds/dds_transport.hpp"
#include "transport/lcm/lcm_transport.hpp"
#include "transport/transport.hpp"
#include "util/cpu_affinity.hpp"

namespace rigid::bench {
namespace {

std::int64_t clock_ns(clockid_t clock) {
  timespec ts{};
  clock_gettime(clock, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

// One bus: its server-side transport and the state it serves.
class Echo final : public transport::Receiver {
 public:
  Echo(Bus bus, const EchoOptions& o) : at_once_(o.at_once), dt_(1.0 / o.rate_hz) {
    const auto n = static_cast<std::size_t>(o.bodies);
    frame_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      frame_.ids[i] = static_cast<std::int32_t>(i);
      frame_.orientation[4 * i] = 1.0;
      frame_.linear_velocity[3 * i] = 1e-3 + 1e-6 * static_cast<double>(i);
    }
    std::unique_ptr<transport::Transport> t;
    if (bus == Bus::kDds) {
      transport::dds::Options d;
      d.role = transport::Role::kServer;
      d.prefix = o.prefix;
      t = transport::dds::make_transport(d, *this);
    } else {
      transport::lcm::Options l;
      l.role = transport::Role::kServer;
      l.prefix = o.prefix;
      t = transport::lcm::make_transport(l, *this);
    }
    // The transport's thread may call on_wrench before make_transport returns: until it is set
    // here, a push only marks the state for the next tick.
    const std::lock_guard lock(mutex_);
    transport_ = std::move(t);
  }
  // The transport first: its thread calls on_wrench until it is gone (and, from the moment it is
  // taken out here, publishes nothing more).
  ~Echo() override {
    std::unique_ptr<transport::Transport> t;
    {
      const std::lock_guard lock(mutex_);
      t = std::move(transport_);
    }
    t.reset();
  }
  Echo(const Echo&) = delete;
  Echo& operator=(const Echo&) = delete;

  // The bus's receive thread. A unit mass pushed for one tick: its velocity changes by f dt.
  void on_wrench(const WrenchCommand& w, const transport::Origin& /*origin*/) override {
    const std::lock_guard lock(mutex_);
    if (w.body_id < 0 || static_cast<std::size_t>(w.body_id) >= frame_.body_count()) return;
    frame_.linear_velocity[3 * static_cast<std::size_t>(w.body_id)] += w.force[0] * dt_;
    pushed_ = true;
    if (at_once_) publish_locked();
  }

  // The tick thread, after each tick: the state goes out if a wrench arrived since the last one
  // went out, or when `periodic`.
  void tick(bool periodic) {
    const std::lock_guard lock(mutex_);
    if (pushed_ || periodic) publish_locked();
  }
  std::int64_t failures() {
    const std::lock_guard lock(mutex_);
    return failures_;
  }

 private:
  void publish_locked() {
    if (!transport_) return;
    frame_.tick = ++tick_;
    frame_.sim_time = static_cast<double>(tick_) * dt_;
    frame_.stamp_ns = clock_ns(CLOCK_REALTIME);
    pushed_ = false;
    if (transport_->publish(frame_) != transport::PublishResult::kOk) ++failures_;
  }

  const bool at_once_;
  const double dt_;
  std::mutex mutex_;
  rigid::StateFrame frame_;
  std::int64_t tick_ = 0;
  bool pushed_ = false;
  std::int64_t failures_ = 0;
  std::unique_ptr<transport::Transport> transport_;
};

// As rigidd's loop: pinned to the last CPU this process may use, then SCHED_FIFO 10. Whether it
// got the priority.
bool make_realtime() {
  if (const int cpu = util::last_allowed_cpu(); cpu >= 0)
    (void)util::pin_to_cpu(pthread_self(), cpu);
  prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);
  sched_param param{};
  param.sched_priority = 10;
  return pthread_setschedparam(pthread_self(), SCHED_FIFO, &param) == 0;
}

bool stop_requested() {
  sigset_t pending;
  sigemptyset(&pending);
  sigpending(&pending);
  return sigismember(&pending, SIGTERM) == 1 || sigismember(&pending, SIGINT) == 1;
}

}  // namespace

int run_echo_server(const EchoOptions& o) {
  // Blocked before any thread starts, so that every thread inherits the mask: the signals stay
  // pending for the tick loop to see, and the process ends through the destructors.
  sigset_t stop;
  sigemptyset(&stop);
  sigaddset(&stop, SIGTERM);
  sigaddset(&stop, SIGINT);
  pthread_sigmask(SIG_BLOCK, &stop, nullptr);
  try {
    std::vector<std::unique_ptr<Echo>> echoes;
    for (const Bus bus : o.buses)
      echoes.push_back(std::make_unique<Echo>(bus, o));
    // After the transports' threads started: they stay at normal priority, on any CPU.
    const bool fifo = make_realtime();
    std::fprintf(stderr, "echo server: %d bodies, %d Hz, %s%s\n", o.bodies, o.rate_hz,
                 o.at_once ? "answering each wrench as it arrives" : "answering after each tick",
                 fifo ? "" : " (no SCHED_FIFO)");
    const std::int64_t period = 1'000'000'000 / o.rate_hz;
    constexpr std::int64_t kSpinNs = 100'000;  // rigidd's --spin-us default
    std::int64_t deadline = clock_ns(CLOCK_MONOTONIC) + period;
    for (std::int64_t k = 1; !stop_requested(); ++k, deadline += period) {
      const std::int64_t wake = deadline - kSpinNs;
      const timespec ts{static_cast<time_t>(wake / 1'000'000'000),
                        static_cast<long>(wake % 1'000'000'000)};
      clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr);
      while (clock_ns(CLOCK_MONOTONIC) < deadline) {
      }
      for (auto& e : echoes)
        e->tick(k % o.publish_every == 0);
      // Late by more than a tick: the next deadline a tick from now, as rigidd skips ticks.
      const std::int64_t now = clock_ns(CLOCK_MONOTONIC);
      if (now - deadline > period) deadline = now;
    }
    std::int64_t failures = 0;
    for (auto& e : echoes)
      failures += e->failures();
    std::fprintf(stderr, "echo server: stopped, %lld publish failures\n",
                 static_cast<long long>(failures));
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "echo server: %s\n", e.what());
    return 1;
  }
}

}  // namespace rigid::bench
