// Runs a Loop on its own thread with an in-memory output, and feeds it commands as the intake
// would. Storage is reserved up front so that recording allocates nothing (the allocation test
// runs the loop thread through it).
#pragma once

#include <gtest/gtest.h>

#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

#include "loop/clock.hpp"
#include "loop/loop.hpp"
#include "scene/scene.hpp"
#include "transport/null_transport.hpp"
#include "transport/transport.hpp"

namespace rigid::loop::testing {

class Recorder : public LoopOutput {
 public:
  Recorder() {
    ticks.reserve(1 << 20);
    tick_ns.reserve(1 << 20);
    replies.reserve(1 << 12);
    contacts.reserve(1 << 16);
    journaled.reserve(1 << 12);
  }
  void offer_state(const rigid::StateFrame& frame, std::int64_t /*arrival_ns*/) override {
    const std::int64_t now = monotonic_ns();
    {
      const std::lock_guard lock(mutex);
      last = frame;  // same shape every time: reuses the vectors
      if (ticks.size() < ticks.capacity()) {
        ticks.push_back(frame.tick);
        tick_ns.push_back(now);
      }
      ++states;
    }
    changed.notify_all();
  }
  void reply(const Reply& r) override {
    {
      const std::lock_guard lock(mutex);
      if (replies.size() < replies.capacity()) replies.push_back(r);
    }
    changed.notify_all();
  }
  // Each event of each tick, flattened (the capacity reserved: recording allocates nothing).
  struct Contact {
    std::int64_t tick = 0;
    double sim_time = 0.0;
    std::int64_t dropped = 0;
    rigid::ContactKind kind = rigid::ContactKind::kImpact;
    std::int32_t body = 0;
    std::int32_t part = 0;
    double time = 0.0;
    rigid::Vec3 position{}, normal{}, impulse{};
  };
  void offer_contacts(const rigid::ContactEvents& e) override {
    {
      const std::lock_guard lock(mutex);
      ++contact_ticks;
      for (std::size_t i = 0; i < e.event_count() && contacts.size() < contacts.capacity(); ++i) {
        Contact c;
        c.tick = e.tick;
        c.sim_time = e.sim_time;
        c.dropped = e.dropped;
        c.kind = e.kinds[i];
        c.body = e.bodies[i];
        c.part = e.parts[i];
        c.time = e.times[i];
        for (std::size_t k = 0; k < 3; ++k) {
          c.position[k] = e.position[3 * i + k];
          c.normal[k] = e.normal[3 * i + k];
          c.impulse[k] = e.impulse[3 * i + k];
        }
        contacts.push_back(c);
      }
    }
    changed.notify_all();
  }
  void journal(const common::JournalEntry& e) override {
    const std::lock_guard lock(mutex);
    if (journaled.size() < journaled.capacity()) journaled.push_back(e);
  }

  std::mutex mutex;
  std::condition_variable changed;
  rigid::StateFrame last;
  std::vector<std::int64_t> ticks;
  // When the loop thread handed each of those states over (CLOCK_MONOTONIC ns): the loop's own
  // pace, which a stall of the test's thread does not change.
  std::vector<std::int64_t> tick_ns;
  std::vector<Reply> replies;
  std::vector<common::JournalEntry> journaled;  // the first 4096 entries
  std::int64_t states = 0;
  std::vector<Contact> contacts;
  std::int64_t contact_ticks = 0;  // offer_contacts calls
};

inline scene::Scene make_scene(const std::string& text) {
  return scene::parse_scene(text, "test.pbtxt");
}

class Harness {
 public:
  Harness(const scene::Scene& scene, rigid::Mode mode, std::size_t queue = 256)
      : queue_(queue), loop_(scene.world, config(scene, mode), queue_, doorbell_, rejects_, out) {
    // Give the recorder's frame its final shape before the loop runs.
    out.last.resize(static_cast<std::size_t>(scene.world.bodies.size()));
  }
  ~Harness() { stop(); }

  static LoopConfig config(const scene::Scene& scene, rigid::Mode mode) {
    LoopConfig c;
    c.mode = mode;
    c.tick_dt = 1.0 / scene.rate_hz;
    c.substeps = scene.substeps;
    c.publish_every = scene.publish_every;
    return c;
  }

  // `body` runs the loop; the default is loop.run(), a test may wrap it.
  void start(std::function<void(Loop&)> body = [](Loop& l) { l.run(); }) {
    thread_ = std::thread([this, body] { body(loop_); });
  }
  void stop() {
    if (!thread_.joinable()) return;
    loop_.request_stop();
    thread_.join();
  }

  void push(const Command& c) {
    ASSERT_TRUE(queue_.try_push(c));
    doorbell_.ring();
  }
  void control(rigid::ControlKind kind, std::int64_t seq, std::int64_t steps = 0, double rtf = 0.0,
               std::int64_t source = 100) {
    Command c;
    c.what = Control{source, seq, kind, steps, rtf};
    push(c);
  }
  void wrench(const Wrench& w) {
    Command c;
    c.what = w;
    push(c);
  }
  void edit(const Edit& e) {
    Command c;
    c.what = e;
    push(c);
  }

  // Waits (at most `patience`) until pred() holds, with the recorder locked.
  template <class Pred>
  bool wait(Pred pred, std::chrono::milliseconds patience = std::chrono::milliseconds(5000)) {
    std::unique_lock lock(out.mutex);
    return out.changed.wait_for(lock, patience, pred);
  }
  // Waits for the reply to `seq` and returns it (outcome kFailed with seq -1 if none came).
  Reply reply_to(std::int64_t seq) {
    Reply found{};
    found.seq = -1;
    found.outcome = rigid::Outcome::kFailed;
    wait([&] {
      for (const Reply& r : out.replies)
        if (r.seq == seq) {
          found = r;
          return true;
        }
      return false;
    });
    return found;
  }
  rigid::StateFrame last_state() {
    const std::lock_guard lock(out.mutex);
    return out.last;
  }

  Loop& loop() { return loop_; }
  RejectCounters& rejects() { return rejects_; }
  Recorder out;

 private:
  BoundedQueue<Command> queue_;
  Doorbell doorbell_;
  RejectCounters rejects_;
  Loop loop_;
  std::thread thread_;
};

}  // namespace rigid::loop::testing
