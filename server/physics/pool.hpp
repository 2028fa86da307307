// A fixed pool of threads for World::step: created once (World construction or set_threads),
// reused for every step. A run hands each thread k in [0, size) one call job(ctx, k), the calling
// thread taking k = 0, and returns once all are done: no allocation, no locking. The job decides
// what k does, so that the split of the work, and thus every result, is the caller's alone.
//
// Hand-over: a run publishes a new generation, which the workers wait for; the caller waits for
// a count of running workers to reach zero. A waiting thread polls for a moment and then sleeps
// (std::atomic::wait: a futex). When the caller says that another run follows at once
// (World::step(n)), the workers poll for it instead of sleeping: a thread that sleeps between two
// steps run back to back is woken late and runs its share slower for a while after (its idle CPU
// was given up): on this project's 2-core VM, 10^4 and 10^5 thrusters stepped 1.71-1.79x faster
// on two threads than on one with sleeping workers, 1.93-1.97x with polling ones (forced_bench
// --scaling, side by side). A single step (one rigidd tick) lets them sleep after a moment, so an
// idle pool takes no CPU from anything else.
#pragma once

#include <atomic>
#include <cstdint>
#include <thread>
#include <vector>

namespace rigid::physics::detail {

class Pool {
 public:
  using Job = void (*)(void* ctx, int k);
  // threads >= 1; spawns threads - 1 workers.
  explicit Pool(int threads);
  ~Pool();
  Pool(const Pool&) = delete;
  Pool& operator=(const Pool&) = delete;

  int size() const { return size_; }
  // `another_follows`: the caller will run again as soon as this run returns.
  void run(Job job, void* ctx, bool another_follows = false);
  // The workers' native handles (k = 1 .. size - 1), so that a caller can place them (rigidd keeps
  // them off the CPU its real-time loop is pinned to).
  const std::vector<std::thread::native_handle_type>& worker_handles() const { return handles_; }

 private:
  void work(int k);
  int size_;
  // Written by the caller before it publishes a generation, read by the workers after they saw it.
  Job job_ = nullptr;
  void* ctx_ = nullptr;
  bool stop_ = false;
  bool another_follows_ = false;
  // Each on a cache line of its own: the workers poll the first, the caller the second.
  alignas(64) std::atomic<std::uint32_t> generation_{0};
  alignas(64) std::atomic<std::uint32_t> running_{0};
  std::vector<std::thread> workers_;
  std::vector<std::thread::native_handle_type> handles_;
};

}  // namespace rigid::physics::detail
