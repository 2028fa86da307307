// A fixed pool of threads for World::step: created once (World construction or set_threads),
// reused for every step. A run hands each thread k in [0, size) one call job(ctx, k), the calling
// thread taking k = 0, and returns once all are done: two barrier phases (start, done) per run, no
// allocation, no other locking. The job decides what k does, so that the split of the work, and
// thus every result, is the caller's alone.
#pragma once

#include <barrier>
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
  void run(Job job, void* ctx);
  // The workers' native handles (k = 1 .. size - 1), so that a caller can place them (rigidd keeps
  // them off the CPU its real-time loop is pinned to).
  const std::vector<std::thread::native_handle_type>& worker_handles() const { return handles_; }

 private:
  void work(int k);
  int size_;
  std::barrier<> start_, done_;
  Job job_ = nullptr;
  void* ctx_ = nullptr;
  bool stop_ = false;
  std::vector<std::thread> workers_;
  std::vector<std::thread::native_handle_type> handles_;
};

}  // namespace rigid::physics::detail
