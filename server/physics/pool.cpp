#include "physics/pool.hpp"

#include <pthread.h>

#include <algorithm>
#include <chrono>
#include <string>

namespace rigid::physics::detail {
namespace {

// How long a waiting thread polls before it sleeps: between steps run back to back, longer than
// any one step of a world big enough to be split (its shares take microseconds to milliseconds);
// otherwise a moment, which covers a chunk finishing just after the caller's last.
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

// The claim word's fields (pool.hpp).
constexpr std::uint64_t claim_word(std::uint32_t gen, std::uint32_t next, std::uint32_t count) {
  return (std::uint64_t{gen} << 32) | (std::uint64_t{next} << 16) | count;
}
constexpr std::uint32_t claim_gen(std::uint64_t w) {
  return static_cast<std::uint32_t>(w >> 32);
}
constexpr std::uint32_t claim_next(std::uint64_t w) {
  return (w >> 16) & 0xffffu;
}
constexpr std::uint32_t claim_count(std::uint64_t w) {
  return w & 0xffffu;
}

}  // namespace

Pool::Pool(int threads) : size_(threads) {
  workers_.reserve(static_cast<std::size_t>(threads - 1));
  handles_.reserve(static_cast<std::size_t>(threads - 1));
  for (int k = 1; k < threads; ++k) {
    workers_.emplace_back([this] { work(); });
    handles_.push_back(workers_.back().native_handle());
    // "rigid-step-K", as rigid's other threads are named (util/thread_name.hpp, which the
    // physics may not include): a profile or top -H then tells the step's threads apart. Cut to
    // the 15 bytes Linux keeps (K >= 10^4), which it would otherwise refuse.
    const std::string name = "rigid-step-" + std::to_string(k);
    (void)pthread_setname_np(handles_.back(), name.substr(0, 15).c_str());
  }
}

Pool::~Pool() {
  stop_.store(true, std::memory_order_relaxed);  // published with the new generation
  generation_.fetch_add(1, std::memory_order_release);
  generation_.notify_all();
  for (std::thread& t : workers_)
    t.join();
}

void Pool::run_chunks(std::uint32_t gen) {
  std::uint64_t w = claim_.load(std::memory_order_acquire);
  for (;;) {
    if (claim_gen(w) != gen || claim_next(w) >= claim_count(w)) return;
    if (!claim_.compare_exchange_weak(w, w + (std::uint64_t{1} << 16), std::memory_order_acquire,
                                      std::memory_order_acquire))
      continue;  // w now holds the current word
    // The chunk is ours: the caller cannot publish another run (and rewrite job_ and ctx_)
    // before it is done.
    job_(ctx_, static_cast<int>(claim_next(w)));
    // The count from our own copy of the word: once the last chunk is counted the caller may
    // publish the next run.
    if (done_.fetch_add(1, std::memory_order_acq_rel) + 1 == claim_count(w)) done_.notify_one();
    w = claim_.load(std::memory_order_acquire);
  }
}

void Pool::work() {
  std::uint32_t seen = 0;
  std::chrono::microseconds poll = kPollOtherwise;
  for (;;) {
    seen = await_change(generation_, seen, poll);
    if (stop_.load(std::memory_order_relaxed)) return;
    poll = std::chrono::microseconds(poll_us_.load(std::memory_order_relaxed));
    // An expect_run's generation has nothing to claim: this returns at once and the worker polls
    // for the run that follows.
    run_chunks(seen);
  }
}

void Pool::expect_run(std::int64_t within_ns) {
  if (size_ == 1) return;
  const std::int64_t ns = std::clamp<std::int64_t>(within_ns, 0, kMaxExpectNs);
  poll_us_.store(ns / 1000 + kPollOtherwise.count(), std::memory_order_relaxed);
  // A new generation without a claim word of its own: claim_ still names the last run, so a
  // worker finds nothing to claim under this one's number.
  generation_.store(generation_.load(std::memory_order_relaxed) + 1, std::memory_order_release);
  generation_.notify_all();
}

void Pool::run(Job job, void* ctx, int chunks, bool another_follows) {
  if (size_ == 1) {
    for (int c = 0; c < chunks; ++c)
      job(ctx, c);
    return;
  }
  const auto count = static_cast<std::uint32_t>(chunks);
  job_ = job;
  ctx_ = ctx;
  poll_us_.store((another_follows ? kPollBetweenSteps : kPollOtherwise).count(),
                 std::memory_order_relaxed);
  done_.store(0, std::memory_order_relaxed);
  const std::uint32_t gen = generation_.load(std::memory_order_relaxed) + 1;
  claim_.store(claim_word(gen, 0, count), std::memory_order_release);
  generation_.store(gen, std::memory_order_release);
  generation_.notify_all();
  run_chunks(gen);
  const auto poll = another_follows ? kPollBetweenSteps : kPollOtherwise;
  for (std::uint32_t d = done_.load(std::memory_order_acquire); d != count;)
    d = await_change(done_, d, poll);
}

}  // namespace rigid::physics::detail
