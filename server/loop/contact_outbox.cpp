#include "loop/contact_outbox.hpp"

#include <stdexcept>

namespace rigid::loop {

ContactOutbox::ContactOutbox(std::size_t ticks, std::size_t events) : ticks_(ticks), rows_(events) {
  if (ticks == 0 || events == 0) throw std::logic_error("ContactOutbox: no room");
}

bool ContactOutbox::has_room(std::size_t events) const {
  const std::uint64_t ticks_used =
      tick_head_.load(std::memory_order_relaxed) - tick_tail_.load(std::memory_order_acquire);
  const std::uint64_t events_used =
      event_head_.load(std::memory_order_relaxed) - event_tail_.load(std::memory_order_acquire);
  return ticks_used < ticks_.size() && events_used + events <= rows_.size();
}

bool ContactOutbox::put(const rigid::ContactEvents& in, std::int64_t stamp_ns) {
  const std::size_t n = in.event_count();
  if (!in.lengths_agree() || !has_room(n)) return false;
  const std::uint64_t first = event_head_.load(std::memory_order_relaxed);
  for (std::size_t i = 0; i < n; ++i) {
    Row& r = rows_[(first + i) % rows_.size()];
    r.kind = in.kinds[i];
    r.body = in.bodies[i];
    r.part = in.parts[i];
    r.time = in.times[i];
    for (std::size_t k = 0; k < 3; ++k) {
      r.position[k] = in.position[3 * i + k];
      r.normal[k] = in.normal[3 * i + k];
      r.impulse[k] = in.impulse[3 * i + k];
    }
  }
  const std::uint64_t head = tick_head_.load(std::memory_order_relaxed);
  Tick& t = ticks_[head % ticks_.size()];
  t.tick = in.tick;
  t.sim_time = in.sim_time;
  t.stamp_ns = stamp_ns;
  t.dropped = in.dropped;
  t.first = first;
  t.count = static_cast<std::uint32_t>(n);
  event_head_.store(first + n, std::memory_order_relaxed);
  // Release: the rows and the tick before the consumer's acquire of the head.
  tick_head_.store(head + 1, std::memory_order_release);
  return true;
}

bool ContactOutbox::take(rigid::ContactEvents& out) {
  const std::uint64_t tail = tick_tail_.load(std::memory_order_relaxed);
  if (tail == tick_head_.load(std::memory_order_acquire)) return false;
  const Tick& t = ticks_[tail % ticks_.size()];
  out.tick = t.tick;
  out.sim_time = t.sim_time;
  out.stamp_ns = t.stamp_ns;
  out.dropped = t.dropped;
  out.resize(t.count);
  for (std::size_t i = 0; i < t.count; ++i) {
    const Row& r = rows_[(t.first + i) % rows_.size()];
    out.kinds[i] = r.kind;
    out.bodies[i] = r.body;
    out.parts[i] = r.part;
    out.times[i] = r.time;
    for (std::size_t k = 0; k < 3; ++k) {
      out.position[3 * i + k] = r.position[k];
      out.normal[3 * i + k] = r.normal[k];
      out.impulse[3 * i + k] = r.impulse[k];
    }
  }
  // Release: the rows and the tick are read before the producer may reuse them.
  event_tail_.store(t.first + t.count, std::memory_order_release);
  tick_tail_.store(tail + 1, std::memory_order_release);
  return true;
}

}  // namespace rigid::loop
