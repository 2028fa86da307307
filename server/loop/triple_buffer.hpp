// Hands the newest value from one writer thread to one reader thread without either waiting: three
// buffers, the writer fills one, the reader reads another, and the third holds the newest
// finished value. A value the reader had not taken when a newer one was published is overwritten
// (the reader only ever wants the latest state); publish() reports it so it can be counted.
// Copying into a buffer of the same shape reuses its storage, so with vectors of a fixed size
// nothing allocates after the first values.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>

namespace rigid::loop {

template <class T>
class TripleBuffer {
 public:
  // Each buffer starts as a copy of `initial` (give it the final shape so nothing grows later).
  explicit TripleBuffer(const T& initial) : buffers_{initial, initial, initial} {}
  TripleBuffer(const TripleBuffer&) = delete;
  TripleBuffer& operator=(const TripleBuffer&) = delete;

  // Writer: the buffer to fill next.
  T& back() { return buffers_[back_]; }
  // Writer: makes back() the newest value. true if the previous newest was never taken.
  bool publish() {
    const std::uint8_t old = middle_.exchange(back_ | kFresh, std::memory_order_acq_rel);
    back_ = old & kIndex;
    return (old & kFresh) != 0;
  }

  // Writer: true while the newest published value has not been taken (a publish() now would
  // overwrite it). The loop waits on this when every state must reach the buses.
  bool pending() const { return (middle_.load(std::memory_order_acquire) & kFresh) != 0; }

  // Reader: the newest value if one was published since the last take, else null. The value
  // stays valid (and the reader may modify it) until the next take.
  T* take() {
    if ((middle_.load(std::memory_order_acquire) & kFresh) == 0) return nullptr;
    const std::uint8_t old = middle_.exchange(front_, std::memory_order_acq_rel);
    front_ = old & kIndex;
    return &buffers_[front_];
  }

 private:
  static constexpr std::uint8_t kIndex = 0x3;
  static constexpr std::uint8_t kFresh = 0x4;
  std::array<T, 3> buffers_;
  std::uint8_t back_ = 0;                // writer's
  std::atomic<std::uint8_t> middle_{1};  // the newest finished one, with kFresh if not taken
  std::uint8_t front_ = 2;               // reader's
};

}  // namespace rigid::loop
