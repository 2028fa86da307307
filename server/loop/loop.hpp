// The fixed-rate loop: the one thread that owns the physics World.
//
// Each tick: drain the command queue (wrenches into the wrench table, controls and edits carried
// out and answered), load the live wrenches into the world, run `substeps` physics steps, drop
// expired wrenches, and hand a state to the publishers every `publish_every` ticks. Modes:
//   realtime  ticks sleep to absolute deadlines on CLOCK_MONOTONIC (fixed_rate_schedule.hpp:
//             overruns are counted and skipped; simulated time stays tick * dt), at a real-time
//             factor a client can set;
//   fast      ticks run back to back, as fast as the CPU allows;
//   lockstep  ticks run only on step requests (for controllers that act every tick).
// A tick in which a new wrench took effect also publishes its state, so a controller sees the
// effect of its command one tick after it arrived instead of up to publish_every ticks later. An
// edit is made between two ticks, at tick T (its answer's tick): running, the state of tick T + 1
// is published, the first stepped from it; paused (or between lockstep steps), the edited state
// is published at once as tick T, so that a paused world shows it.
// Every command carried out goes to the output's journal with its tick (journal_entry.hpp), and
// with hash_states a hash of every published state too, so that a replay can reproduce the run.
// Paused (or in lockstep with no step requested) the loop waits on the command doorbell and
// republishes the unchanged state once a second for late subscribers. The ticks of a step request
// (every tick in lockstep) publish every state publish_every promises: before handing over a
// state the loop waits until the publishers have taken the previous one, so publishing paces the
// steps instead of skipping states (bounded: see wait_for_publishers). A body the physics guard
// freezes (physics/world.hpp) is counted in the summary and queued once for the log. After each
// tick's steps the world's contact events (a scene with static parts) go to the output as one
// ContactEvents message for that tick, if there are any, and with hash_states their hash to the
// journal; the ticks of a step request wait for the buses' room for them as they wait for a state.
//
// run() allocates nothing: everything is sized in the constructor (tests/loop proves it).
#pragma once

#include <atomic>
#include <cstdint>
#include <vector>

#include "common/driven_world.hpp"
#include "loop/bounded_queue.hpp"
#include "loop/command.hpp"
#include "loop/doorbell.hpp"
#include "loop/fixed_rate_schedule.hpp"
#include "loop/outbox.hpp"
#include "loop/reject_counters.hpp"
#include "loop/sequence_table.hpp"
#include "loop/tick_stats.hpp"
#include "loop/triple_buffer.hpp"
#include "physics/world.hpp"
#include "rigid/messages.hpp"

namespace rigid::loop {

// A body the physics guard froze (physics::World::frozen_bodies), for the log: the loop thread
// cannot log, so it queues these for the server's housekeeping thread.
struct FrozenBody {
  std::int32_t body = 0;
  std::int64_t tick = 0;  // the first tick after which it was found frozen
};

struct LoopConfig {
  rigid::Mode mode = rigid::Mode::kRealtime;
  double tick_dt = 1e-3;  // s: 1 / rate_hz
  int substeps = 1;
  int publish_every = 1;
  std::size_t wrench_capacity = 4096;  // live (source, body, key) entries
  std::size_t source_capacity = 1024;  // sources whose sequence numbers are remembered
  std::size_t wrench_share = 64;       // live wrenches one sender may hold (limits)
  // Realtime: sleep to this long before each deadline, then busy-wait to it. A sleeping thread
  // can wake tens of microseconds late (timer and scheduler latency, the more so in a VM); the
  // spin takes that out of tick lateness for spin_ns / period of one core. 0: sleep only.
  std::int64_t spin_ns = 100'000;
  // Journal a hash of every state published (rigidd --journal): one pass over the state per
  // publish (state_hash.hpp says what it costs).
  bool hash_states = false;
  // The output lends the frame each state is written into (LoopOutput::lend_frame): the loop then
  // keeps no state frame of its own (a state is ~108 B a body).
  bool output_lends_frames = false;
};

class Loop {
 public:
  Loop(const physics::WorldSpec& spec, const LoopConfig& config, BoundedQueue<Command>& commands,
       Doorbell& doorbell, RejectCounters& rejects, LoopOutput& output);
  Loop(const Loop&) = delete;
  Loop& operator=(const Loop&) = delete;

  // Runs on the calling thread until request_stop(); returns within ~100 ms of it.
  void run();

  // Any thread.
  void request_stop();
  // Advances on every pass of the loop, ticking or waiting for commands (at least every 100 ms):
  // the watchdog's proof that the loop thread is alive.
  std::uint64_t heartbeat() const { return heartbeat_.load(std::memory_order_relaxed); }
  std::int64_t commands_accepted() const { return accepted_.load(std::memory_order_relaxed); }
  std::int64_t overruns() const { return overruns_.load(std::memory_order_relaxed); }
  // One reader thread: the newest one-second summary, if one came since the last call.
  bool take_summary(LoopSummary& out);
  // One reader thread: the next body frozen for the first time in this run, if any. Each body
  // comes at most once (the queue holds one entry per body: none is ever lost).
  bool take_frozen(FrozenBody& out) { return frozen_events_.try_pop(out); }

  // After run() has returned (or before it started).
  RunTotals totals() const;
  const physics::World& world() const { return driven_.world(); }
  std::int64_t tick() const { return driven_.tick(); }

 private:
  bool wants_tick() const;
  double period_ns() const;  // of the wall clock between ticks, at the real-time factor
  void drain();
  void handle(const Command& c);
  void handle_wrench(const Command& c, const Wrench& w);
  void refuse_wrench(const Command& c, const Wrench& w, RejectReason reason, const char* detail);
  void handle_control(const Command& c, const Control& k);
  void answer(const Command& c, const Control& k, rigid::Outcome outcome,
              ReplyNote note = ReplyNote::kNone, std::int64_t detail = 0);
  void handle_edit(const Command& c, const Edit& e);
  void do_reset();
  void step_tick();
  // paced: every state must reach the buses (wait_for_publishers first).
  void publish_state(bool paced = false);
  // Waits until the publishers have taken the last state, in slices of at most 100 ms (the
  // heartbeat advances, a stop request ends the wait); after kMaxPaceWaitNs the next state
  // replaces the one not taken (counted as skipped), so that a bus that stopped sending cannot
  // hold the world forever.
  void wait_for_publishers();
  static constexpr std::int64_t kMaxPaceWaitNs = 1'000'000'000;
  void journal_control(const Control& k);
  // Sleeps to config_.spin_ns before the deadline in slices of at most 100 ms, then spins to it;
  // false if a stop was requested.
  bool sleep_to(std::int64_t deadline_ns);
  void idle_wait();
  // A loop that has not slept for kMaxBusyNs (behind schedule, or running a long step request)
  // sleeps kRestNs: at real-time priority it would otherwise starve the publishers pinned to its
  // CPU, and replies and states would stop going out. It then falls behind a little more
  // (overruns, rtf in Stats) instead.
  void rest_if_busy();
  static constexpr std::int64_t kMaxBusyNs = 5'000'000;
  static constexpr std::int64_t kRestNs = 200'000;
  void roll_stats(std::int64_t now_ns);
  void note_frozen_bodies();
  // The contact events of the tick just stepped, to the output (and their hash to the journal).
  void collect_contacts(bool paced);

  const LoopConfig config_;
  common::DrivenWorld driven_;  // the world, its acting wrenches and the tick counter
  BoundedQueue<Command>& commands_;
  Doorbell& doorbell_;
  RejectCounters& rejects_;
  LoopOutput& output_;

  SequenceTable wrench_sources_;
  SequenceTable control_sources_;
  SequenceTable edit_sources_;
  rigid::StateFrame frame_;
  FixedRateSchedule schedule_;
  TickStats stats_;
  TripleBuffer<LoopSummary> summaries_;

  double rtf_ = 1.0;
  bool paused_ = false;
  bool on_schedule_ = false;    // realtime: the schedule's origin is valid
  bool new_command_ = false;    // a wrench took effect since the last tick
  std::int64_t step_left_ = 0;  // ticks left of the running step request
  std::int64_t step_total_ = 0;
  rigid::Bus step_bus_ = rigid::Bus::kDds;  // the running step request's, for its answer
  Control step_request_{};
  std::int64_t last_publish_ns_ = 0;
  std::int64_t first_arrival_ns_ = 0;  // of the commands not yet shown in a published state
  std::int64_t hashed_tick_ = -1;      // the last state hashed (an idle republish is not again)
  std::int64_t last_rest_ns_ = 0;      // when the loop last slept (see rest_if_busy)

  // Physics faults. The world lists its frozen bodies in order; frozen_seen_ of them have been
  // looked at (a reset empties the list). Each body is queued for the log the first time only.
  BoundedQueue<FrozenBody> frozen_events_;
  std::vector<std::uint8_t> frozen_reported_;  // by body id
  std::size_t frozen_seen_ = 0;
  std::int64_t large_rotations_before_reset_ = 0;  // the world's count restarts at each reset

  // Contact events: the message each tick's events are written into (room for a full tick made
  // once, for a world with static parts), and the physics' dropped events before the last reset.
  rigid::ContactEvents contacts_;
  std::int64_t contacts_dropped_before_reset_ = 0;

  std::atomic<bool> stop_{false};
  std::atomic<std::uint64_t> heartbeat_{0};
  std::atomic<std::int64_t> accepted_{0};
  std::atomic<std::int64_t> overruns_{0};
};

}  // namespace rigid::loop
