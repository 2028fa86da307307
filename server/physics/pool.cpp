#include "physics/pool.hpp"

#include <chrono>

namespace rigid::physics::detail {
namespace {

// How long a waiting thread polls before it sleeps: between steps run back to back, longer than
// any one step of a world big enough to be split (its shares take microseconds to milliseconds);
// otherwise a moment, which covers a share finishing just after the caller's.
constexpr std::chrono::microseconds kPollBetweenSteps{10000};
constexpr std::chrono::microseconds kPollOtherwise{20};

inline void relax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#endif
}

// Waits until `value` is no longer `old` and returns it: polling for `poll`, then sleeping.
std::uint32_t await_change(const std::atomic<std::uint32_t>& value, std::uint32_t old,
                           std::chrono::microseconds poll) {
  const auto until = std::chrono::steady_clock::now() + poll;
  for (unsigned i = 1;; ++i) {
    const std::uint32_t now = value.load(std::memory_order_acquire);
    if (now != old) return now;
    if (i % 64 == 0 && std::chrono::steady_clock::now() >= until) break;
    relax();
  }
  for (;;) {
    value.wait(old, std::memory_order_acquire);
    const std::uint32_t now = value.load(std::memory_order_acquire);
    if (now != old) return now;
  }
}

}  // namespace

Pool::Pool(int threads) : size_(threads) {
  workers_.reserve(static_cast<std::size_t>(threads - 1));
  handles_.reserve(static_cast<std::size_t>(threads - 1));
  for (int k = 1; k < threads; ++k) {
    workers_.emplace_back([this, k] { work(k); });
    handles_.push_back(workers_.back().native_handle());
  }
}

Pool::~Pool() {
  stop_ = true;  // published to the workers with the new generation
  generation_.fetch_add(1, std::memory_order_release);
  generation_.notify_all();
  for (std::thread& t : workers_)
    t.join();
}

void Pool::work(int k) {
  std::uint32_t seen = 0;
  bool poll_long = false;
  for (;;) {
    seen = await_change(generation_, seen, poll_long ? kPollBetweenSteps : kPollOtherwise);
    if (stop_) return;
    poll_long = another_follows_;  // read before the caller may write the next run's
    job_(ctx_, k);
    if (running_.fetch_sub(1, std::memory_order_acq_rel) == 1) running_.notify_one();
  }
}

void Pool::run(Job job, void* ctx, bool another_follows) {
  if (size_ == 1) {
    job(ctx, 0);
    return;
  }
  job_ = job;
  ctx_ = ctx;
  another_follows_ = another_follows;
  running_.store(static_cast<std::uint32_t>(size_ - 1), std::memory_order_relaxed);
  generation_.fetch_add(1, std::memory_order_release);
  generation_.notify_all();
  job(ctx, 0);
  const auto poll = another_follows ? kPollBetweenSteps : kPollOtherwise;
  for (std::uint32_t left = running_.load(std::memory_order_acquire); left != 0;) {
    left = await_change(running_, left, poll);
  }
}

}  // namespace rigid::physics::detail
