#include "physics/pool.hpp"

namespace rigid::physics::detail {

Pool::Pool(int threads) : size_(threads), start_(threads), done_(threads) {
  workers_.reserve(static_cast<std::size_t>(threads - 1));
  handles_.reserve(static_cast<std::size_t>(threads - 1));
  for (int k = 1; k < threads; ++k) {
    workers_.emplace_back([this, k] { work(k); });
    handles_.push_back(workers_.back().native_handle());
  }
}

Pool::~Pool() {
  stop_ = true;  // published to the workers by the barrier
  start_.arrive_and_wait();
  for (std::thread& t : workers_)
    t.join();
}

void Pool::work(int k) {
  for (;;) {
    start_.arrive_and_wait();  // job_, ctx_ and stop_ were written before the caller arrived
    if (stop_) return;
    job_(ctx_, k);
    done_.arrive_and_wait();
  }
}

void Pool::run(Job job, void* ctx) {
  if (size_ == 1) {
    job(ctx, 0);
    return;
  }
  job_ = job;
  ctx_ = ctx;
  start_.arrive_and_wait();
  job(ctx, 0);
  done_.arrive_and_wait();
}

}  // namespace rigid::physics::detail
