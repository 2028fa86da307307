// A fixed pool of threads for World::step: created once (World construction or set_threads),
// reused for every step. A run splits the work into `chunks` independent calls job(ctx, c),
// c in [0, chunks), which the calling thread and the workers claim one at a time; it returns once
// every chunk is done: no allocation, no locking. The job decides what chunk c does, so that the
// split of the work, and thus every result, is the caller's alone: which thread runs a chunk
// changes nothing.
//
// Why chunks are claimed rather than handed out one share per thread: a worker that sleeps
// between two rigidd ticks can be woken late (tens to hundreds of microseconds on a busy host)
// and may be preempted by the publishers on its CPU. With a fixed share per thread the tick waits
// for the latest thread's whole share; with claimed chunks the caller starts at once, takes
// whatever the workers have not, and waits only for the chunks already begun. A run is never
// slower than the caller alone by more than one chunk (bench/notes/step-threads.md).
//
// Hand-over: a run publishes one word (its number, the next chunk, the chunk count), which the
// threads advance by compare-and-swap, and a new generation, which the workers wait for; the
// caller waits for the count of finished chunks. A waiting thread polls for a moment and then
// sleeps (std::atomic::wait: a futex). When the caller says that another run follows at once
// (World::step(n)), the workers poll for it instead of sleeping: a thread that sleeps between two
// steps run back to back is woken late and runs its share slower for a while after (its idle CPU
// was given up), which costs a good part of the second thread's gain (bench/notes/
// step-threads.md). A single step (one rigidd tick) lets them sleep after a moment, so an idle
// pool takes no CPU from anything else.
//
// A caller that knows when its next run comes (rigidd's loop, which wakes spin_ns before each
// tick's deadline and spins to it) says so with expect_run: the workers wake now and poll for
// that run, so that they are running when it is published instead of being woken by it; a worker
// woken by the run itself can start tens to hundreds of microseconds late on a busy host, and the
// caller then steps most of the world alone (bench/notes/step-threads.md).
#pragma once

#include <atomic>
#include <cstdint>
#include <thread>
#include <vector>

namespace rigid::physics::detail {

class Pool {
 public:
  using Job = void (*)(void* ctx, int chunk);
  static constexpr int kMaxChunks = 0xffff;
  // threads >= 1; spawns threads - 1 workers.
  explicit Pool(int threads);
  ~Pool();
  Pool(const Pool&) = delete;
  Pool& operator=(const Pool&) = delete;

  int size() const { return size_; }
  // Runs job(ctx, c) once for every c in [0, chunks), chunks in [1, kMaxChunks], on the calling
  // thread and the workers. `another_follows`: the caller will run again as soon as this returns.
  void run(Job job, void* ctx, int chunks, bool another_follows = false);
  // A run follows within `within` (at most kMaxExpectNs): the workers wake now and poll for it
  // until then (and a moment after) instead of sleeping. Publishes nothing to claim: a run already
  // under way, or none at all, is unaffected. Called by the thread that calls run().
  static constexpr std::int64_t kMaxExpectNs = 10'000'000;
  void expect_run(std::int64_t within_ns);
  // The workers' native handles (k = 1 .. size - 1), so that a caller can place them (rigidd keeps
  // them off the CPU its real-time loop is pinned to).
  const std::vector<std::thread::native_handle_type>& worker_handles() const { return handles_; }

 private:
  void work();
  // Claims and runs chunks of run `gen` until none is left or a newer run was published.
  void run_chunks(std::uint32_t gen);
  int size_;
  // Written by the caller before it publishes a run; a worker reads them only after it claimed a
  // chunk of that run, which the caller waits for before it may write the next run's.
  Job job_ = nullptr;
  void* ctx_ = nullptr;
  std::atomic<bool> stop_{false};
  // How long a worker polls for the next generation before it sleeps, in microseconds: set by the
  // caller before it publishes a generation (a run or an expect_run), read by the workers after.
  std::atomic<std::int64_t> poll_us_{0};
  // Each on a cache line of its own. claim_: bits 32-63 the run's generation, 16-31 the next
  // chunk, 0-15 the chunk count. A worker woken late for an old run sees a newer generation here
  // and claims nothing of it under the old one's number.
  alignas(64) std::atomic<std::uint32_t> generation_{0};
  alignas(64) std::atomic<std::uint64_t> claim_{0};
  alignas(64) std::atomic<std::uint32_t> done_{0};
  std::vector<std::thread> workers_;
  std::vector<std::thread::native_handle_type> handles_;
};

}  // namespace rigid::physics::detail
