#include "loop/loop.hpp"

#include <sys/prctl.h>

#include <algorithm>
#include <cstdio>
#include <span>
#include <stdexcept>

#include "common/state_conversion.hpp"
#include "common/state_hash.hpp"
#include "loop/clock.hpp"
#include "loop/intake.hpp"

namespace rigid::loop {
namespace {

using rigid::ControlKind;
using rigid::Mode;
using rigid::Outcome;

constexpr std::int64_t kMaxSleepSliceNs = 100'000'000;  // stop requests are seen within this
constexpr std::int64_t kIdleRepublishNs = 1'000'000'000;

// Tells the CPU this is a spin-wait (saves power, frees the sibling hyper-thread).
inline void cpu_relax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#endif
}

}  // namespace

Loop::Loop(const physics::WorldSpec& spec, const LoopConfig& config,
           BoundedQueue<Command>& commands, Doorbell& doorbell, RejectCounters& rejects,
           LoopOutput& output)
    : config_(config),
      driven_(spec, config.tick_dt, config.substeps, config.wrench_capacity),
      commands_(commands),
      doorbell_(doorbell),
      rejects_(rejects),
      output_(output),
      wrench_sources_(config.source_capacity),
      control_sources_(config.source_capacity),
      edit_sources_(config.source_capacity),
      schedule_(0, config.tick_dt * 1e9),
      stats_(config.tick_dt, 0),
      summaries_(LoopSummary{}),
      frozen_events_(static_cast<std::size_t>(driven_.world().body_count())),
      frozen_reported_(static_cast<std::size_t>(driven_.world().body_count()), 0) {
  if (!config_.output_lends_frames) common::shape_state_frame(driven_.world(), frame_);
  if (driven_.world().static_part_count() > 0) common::reserve_contact_events(contacts_);
  paused_ = config_.mode == Mode::kLockstep;
}

void Loop::request_stop() {
  stop_.store(true, std::memory_order_release);
  doorbell_.ring();
}

bool Loop::take_summary(LoopSummary& out) {
  const LoopSummary* s = summaries_.take();
  if (s == nullptr) return false;
  out = *s;
  return true;
}

RunTotals Loop::totals() const {
  return stats_.totals(monotonic_ns());
}

double Loop::period_ns() const {
  return config_.tick_dt * 1e9 / rtf_;
}

bool Loop::wants_tick() const {
  return step_left_ > 0 || !paused_;
}

void Loop::run() {
  // Timer slack (50 us by default for ordinary threads) would be added to every wake-up.
  prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);
  // The first tick would otherwise make every quiet body's rotor plan, at several times a tick's
  // cost: a late first tick, skipped ticks, in every run (bench/notes/loop-latency.md).
  driven_.prepare_tick();
  const std::int64_t start = monotonic_ns();
  stats_ = TickStats(config_.tick_dt, start);
  publish_state();  // tick 0: subscribers (and systemd's READY=1) need not wait for a tick

  while (!stop_.load(std::memory_order_acquire)) {
    heartbeat_.fetch_add(1, std::memory_order_relaxed);
    if (!wants_tick()) {
      on_schedule_ = false;
      idle_wait();
      continue;
    }
    // A step request runs its ticks back to back; otherwise realtime ticks keep the schedule.
    const bool scheduled = config_.mode == Mode::kRealtime && step_left_ == 0;
    std::int64_t deadline = 0;
    if (scheduled) {
      if (!on_schedule_) {  // (re)starting: the first tick is due now
        schedule_.restart(monotonic_ns(), period_ns());
        on_schedule_ = true;
      }
      deadline = schedule_.deadline();
      if (!sleep_to(deadline)) break;
      stats_.record_lateness(monotonic_ns() - deadline);
    }
    drain();
    if (wants_tick()) {
      step_tick();
      if (scheduled && !on_schedule_) {
        // A new real-time factor or a reset during this tick: the next tick is one new period
        // after this one's deadline.
        schedule_.restart(deadline + static_cast<std::int64_t>(period_ns()), period_ns());
        on_schedule_ = true;
      } else if (scheduled) {
        const std::int64_t skipped = schedule_.advance(monotonic_ns());
        if (skipped > 0) {
          stats_.add_overruns(skipped);
          overruns_.store(stats_.overruns(), std::memory_order_relaxed);
        }
      }
    }
    rest_if_busy();
    const std::int64_t now = monotonic_ns();
    if (stats_.window_due(now)) roll_stats(now);
  }
}

void Loop::rest_if_busy() {
  // Only realtime mode runs at real-time priority (server.cpp); fast and lockstep never starve.
  if (config_.mode != Mode::kRealtime) return;
  const std::int64_t now = monotonic_ns();
  if (now - last_rest_ns_ < kMaxBusyNs) return;
  sleep_until(now + kRestNs);
  last_rest_ns_ = monotonic_ns();
}

bool Loop::sleep_to(std::int64_t deadline_ns) {
  const std::int64_t wake = deadline_ns - config_.spin_ns;
  for (;;) {
    if (stop_.load(std::memory_order_acquire)) return false;
    const std::int64_t now = monotonic_ns();
    if (now >= wake) break;
    sleep_until(std::min(wake, now + kMaxSleepSliceNs));
    // Only a real sleep counts as rest: a deadline microseconds away (a loop behind at a high
    // rate) returns without giving the CPU to anyone.
    if (wake - now >= kRestNs) last_rest_ns_ = monotonic_ns();
  }
  // The step's other threads wake now and poll for it, as this thread spins to it: woken by the
  // step itself they would start late, and this thread would step their share too.
  driven_.expect_tick(deadline_ns - monotonic_ns());
  while (monotonic_ns() < deadline_ns)
    cpu_relax();
  return true;
}

void Loop::idle_wait() {
  const std::uint32_t seen = doorbell_.count();
  drain();
  std::int64_t now = monotonic_ns();
  if (!wants_tick() && !stop_.load(std::memory_order_acquire)) {
    const std::int64_t until = std::min(
        {now + kMaxSleepSliceNs, stats_.window_end_ns(), last_publish_ns_ + kIdleRepublishNs});
    doorbell_.wait_until(seen, until);
    now = monotonic_ns();
    last_rest_ns_ = now;
  }
  if (!wants_tick() && now - last_publish_ns_ >= kIdleRepublishNs) publish_state();
  if (stats_.window_due(now)) roll_stats(now);
}

void Loop::roll_stats(std::int64_t now_ns) {
  const std::int64_t tick = driven_.tick();
  LoopSummary& s = summaries_.back();
  s = stats_.close_window(now_ns, tick, static_cast<double>(tick) * config_.tick_dt, config_.mode,
                          paused_ && step_left_ == 0);
  s.bodies_frozen = static_cast<std::int64_t>(driven_.world().frozen_bodies().size());
  s.large_rotation_steps = large_rotations_before_reset_ + driven_.world().large_rotation_steps();
  summaries_.publish();
}

void Loop::note_frozen_bodies() {
  const std::span<const int> frozen = driven_.world().frozen_bodies();
  for (; frozen_seen_ < frozen.size(); ++frozen_seen_) {
    const auto id = static_cast<std::size_t>(frozen[frozen_seen_]);
    if (frozen_reported_[id] != 0) continue;  // frozen before a reset: logged then
    frozen_reported_[id] = 1;
    // Room for every body once: this push cannot fail.
    (void)frozen_events_.try_push(FrozenBody{static_cast<std::int32_t>(id), driven_.tick()});
  }
}

void Loop::drain() {
  // At most one queue's worth per pass: producers refilling the queue as fast as it empties
  // cannot keep the loop from ticking.
  Command c;
  for (std::size_t n = commands_.capacity(); n > 0 && commands_.try_pop(c); --n)
    handle(c);
}

void Loop::handle(const Command& c) {
  if (const Wrench* w = std::get_if<Wrench>(&c.what)) {
    handle_wrench(c, *w);
  } else if (const Control* k = std::get_if<Control>(&c.what)) {
    handle_control(c, *k);
  } else if (const Edit* e = std::get_if<Edit>(&c.what)) {
    handle_edit(c, *e);
  }
}

// The key sequence numbers are kept by: the sender's bus and session (and identity), and the
// source it writes.
static std::int64_t sequence_key(const Command& c, std::int64_t source) {
  return static_cast<std::int64_t>(
      util::mix64(c.session_key ^ util::mix64(static_cast<std::uint64_t>(source))));
}

void Loop::refuse_wrench(const Command& c, const Wrench& w, RejectReason reason,
                         const char* detail) {
  rejects_.record(reason, detail, &c.sender);
  char why[200];
  std::snprintf(why, sizeof why, "%.*s: %s", static_cast<int>(to_string(reason).size()),
                to_string(reason).data(), detail);
  answer_refused_wrench(output_, rejects_, c.bus, w.source, w.seq, c.sender, why, driven_.tick());
}

void Loop::handle_wrench(const Command& c, const Wrench& w) {
  const std::int64_t arrival_ns = c.arrival_ns;
  std::int64_t last = 0;
  char detail[200];
  if (!wrench_sources_.accept(sequence_key(c, w.source), w.seq, &last)) {
    std::snprintf(detail, sizeof detail,
                  "wrench from %s source %lld: seq %lld is not above this session's last %lld",
                  c.sender.name, static_cast<long long>(w.source), static_cast<long long>(w.seq),
                  static_cast<long long>(last));
    refuse_wrench(c, w, RejectReason::kStaleSequence, detail);
    return;
  }
  switch (driven_.apply(w, c.sender.key, config_.wrench_share)) {
    case common::WrenchTable::Upsert::kFull:
      std::snprintf(detail, sizeof detail,
                    "wrench table full (%zu live wrenches, none held beyond a fair share): wrench "
                    "from %s seq %lld dropped",
                    driven_.wrench_capacity(), c.sender.name, static_cast<long long>(w.seq));
      refuse_wrench(c, w, RejectReason::kQueueFull, detail);
      return;
    case common::WrenchTable::Upsert::kOverShare:
      std::snprintf(detail, sizeof detail,
                    "wrench from %s seq %lld: the sender already holds its %zu live wrenches "
                    "(limits.max_wrenches_per_source)",
                    c.sender.name, static_cast<long long>(w.seq), config_.wrench_share);
      refuse_wrench(c, w, RejectReason::kOverShare, detail);
      return;
    case common::WrenchTable::Upsert::kInserted:
    case common::WrenchTable::Upsert::kReplaced:
      break;
  }
  common::JournalEntry entry;
  entry.tick = driven_.tick();
  entry.what = w;
  output_.journal(entry);
  accepted_.fetch_add(1, std::memory_order_relaxed);
  new_command_ = true;
  if (first_arrival_ns_ == 0) first_arrival_ns_ = arrival_ns;
}

void Loop::answer(const Command& c, const Control& k, Outcome outcome, ReplyNote note,
                  std::int64_t detail) {
  output_.reply(Reply{c.bus, k.source, k.seq, k.kind, outcome, driven_.tick(), note, detail});
}

void Loop::journal_control(const Control& k) {
  common::JournalEntry entry;
  entry.tick = driven_.tick();
  entry.what = k;
  output_.journal(entry);
}

void Loop::handle_edit(const Command& c, const Edit& e) {
  Reply reply{c.bus,          e.source,         e.seq, rigid::kReplyToEdit, Outcome::kOk,
              driven_.tick(), ReplyNote::kNone, 0};
  reply.edit = e.kind;
  std::int64_t last = 0;
  if (!edit_sources_.accept(sequence_key(c, e.source), e.seq, &last)) {
    rejects_.recordf(RejectReason::kStaleSequence, &c.sender,
                     "edit from %s source %lld: seq %lld is not above this session's last %lld",
                     c.sender.name, static_cast<long long>(e.source), static_cast<long long>(e.seq),
                     static_cast<long long>(last));
    reply.outcome = Outcome::kInvalid;
    reply.note = ReplyNote::kStaleSequence;
    reply.detail = last;
    output_.reply(reply);
    return;
  }
  // Validated by the intake: a known kind, a known body, finite numbers, a unit orientation, so
  // the world takes it (World::set_state throws only for a non-finite state).
  driven_.edit(e);
  common::JournalEntry entry;
  entry.tick = driven_.tick();
  entry.what = e;
  output_.journal(entry);
  accepted_.fetch_add(1, std::memory_order_relaxed);
  if (first_arrival_ns_ == 0) first_arrival_ns_ = c.arrival_ns;
  if (wants_tick()) {
    new_command_ = true;  // the next tick's state, the first stepped from the edited one
  } else {
    // Paused: this tick's state again, edited, and hashed again for the journal (a replay checks
    // it after the edit it journaled at this tick). Paced: the state before it (a step's last)
    // is not replaced before the buses have it; and handed over before the answer, which the
    // publishers send after it, so that a client that has the answer has the state too.
    hashed_tick_ = -1;
    publish_state(true);
  }
  output_.reply(reply);
}

void Loop::handle_control(const Command& c, const Control& k) {
  std::int64_t last = 0;
  if (!control_sources_.accept(sequence_key(c, k.source), k.seq, &last)) {
    rejects_.recordf(RejectReason::kStaleSequence, &c.sender,
                     "control from %s source %lld: seq %lld is not above this session's last %lld",
                     c.sender.name, static_cast<long long>(k.source), static_cast<long long>(k.seq),
                     static_cast<long long>(last));
    answer(c, k, Outcome::kInvalid, ReplyNote::kStaleSequence, last);
    return;
  }
  accepted_.fetch_add(1, std::memory_order_relaxed);
  const bool lockstep = config_.mode == Mode::kLockstep;
  switch (k.kind) {
    case ControlKind::kPause:
    case ControlKind::kResume:
      if (lockstep) {
        answer(c, k, Outcome::kNotAllowed, ReplyNote::kLockstepOnlySteps);
        return;
      }
      paused_ = k.kind == ControlKind::kPause;
      journal_control(k);
      answer(c, k, Outcome::kOk);
      return;
    case ControlKind::kStep:
      if (!paused_) {
        answer(c, k, Outcome::kNotAllowed, ReplyNote::kStepNeedsPause);
      } else if (step_left_ > 0) {
        answer(c, k, Outcome::kNotAllowed, ReplyNote::kStepInProgress, step_left_);
      } else {
        // Answered when the last of its ticks is done (step_tick).
        step_left_ = k.steps;
        step_total_ = k.steps;
        step_bus_ = c.bus;
        step_request_ = k;
        journal_control(k);
      }
      return;
    case ControlKind::kReset:
      journal_control(k);  // before do_reset's state at tick 0, in the journal as in the loop
      do_reset();
      answer(c, k, Outcome::kOk);
      return;
    case ControlKind::kSetRtf:
      if (config_.mode != Mode::kRealtime) {
        answer(c, k, Outcome::kNotAllowed, ReplyNote::kRtfNeedsRealtime);
        return;
      }
      rtf_ = k.rtf;
      on_schedule_ = false;  // the next tick starts a schedule with the new period
      journal_control(k);
      answer(c, k, Outcome::kOk);
      return;
    case ControlKind::kNone:
      break;
  }
  // The intake lets only known commands through; answer anyway rather than stay silent.
  answer(c, k, Outcome::kInvalid, ReplyNote::kUnknownCommand);
}

void Loop::do_reset() {
  if (step_left_ > 0) {
    const std::int64_t done = step_total_ - step_left_;
    step_left_ = 0;
    output_.reply(Reply{step_bus_, step_request_.source, step_request_.seq, ControlKind::kStep,
                        Outcome::kFailed, driven_.tick(), ReplyNote::kInterruptedByReset, done});
  }
  large_rotations_before_reset_ += driven_.world().large_rotation_steps();
  contacts_dropped_before_reset_ += driven_.world().contact_events_dropped();
  driven_.reset();         // thaws the frozen bodies
  driven_.prepare_tick();  // the reset made every plan stale: remade now, not in the next tick
  frozen_seen_ = 0;
  new_command_ = false;
  first_arrival_ns_ = 0;
  hashed_tick_ = -1;
  on_schedule_ = false;
  publish_state();
}

void Loop::step_tick() {
  const std::int64_t t0 = monotonic_ns();
  driven_.step_tick();
  stats_.count_tick();
  stats_.record_step_cost(monotonic_ns() - t0);
  note_frozen_bodies();

  const std::int64_t tick = driven_.tick();
  // A tick of a step request (every tick in lockstep) hands over each of its states.
  const bool paced = step_left_ > 0;
  collect_contacts(paced);
  bool publish = tick % config_.publish_every == 0 || new_command_;
  new_command_ = false;
  bool step_done = false;
  if (step_left_ > 0 && --step_left_ == 0) {
    publish = true;  // a stepping controller needs the state its step ended on
    step_done = true;
  }
  if (publish) publish_state(paced);
  if (step_done) {
    output_.reply(Reply{step_bus_, step_request_.source, step_request_.seq, ControlKind::kStep,
                        Outcome::kOk, tick, ReplyNote::kNone, step_total_});
  }
}

void Loop::collect_contacts(bool paced) {
  const std::span<const physics::ContactEvent> events = driven_.world().contact_events();
  if (events.empty()) return;
  const std::int64_t tick = driven_.tick();
  common::fill_contact_events(events, tick, static_cast<double>(tick) * config_.tick_dt, contacts_);
  contacts_.dropped = contacts_dropped_before_reset_ + driven_.world().contact_events_dropped();
  if (config_.hash_states) {
    common::JournalEntry entry;
    entry.tick = tick;
    entry.what = common::ContactsHash{common::contact_hash(contacts_),
                                      static_cast<std::int32_t>(contacts_.event_count())};
    output_.journal(entry);
  }
  if (paced) {
    // As wait_for_publishers: in slices, the heartbeat advancing, a stop ending the wait, and
    // after kMaxPaceWaitNs the events go to whichever bus has room (the others count them lost).
    const std::int64_t give_up = monotonic_ns() + kMaxPaceWaitNs;
    while (!output_.wait_contacts_room(contacts_.event_count(),
                                       std::min(monotonic_ns() + kMaxSleepSliceNs, give_up))) {
      heartbeat_.fetch_add(1, std::memory_order_relaxed);
      if (stop_.load(std::memory_order_acquire) || monotonic_ns() >= give_up) break;
    }
  }
  output_.offer_contacts(contacts_);
}

void Loop::wait_for_publishers() {
  if (config_.mode == Mode::kRealtime) {
    // At real-time priority the loop and its publishers would keep their CPU through a whole step
    // request, and a subscriber that shares that CPU would not run until it ends: its socket
    // overflows and states are lost after all. A short sleep per state lets it keep up.
    sleep_until(monotonic_ns() + kRestNs);
    last_rest_ns_ = monotonic_ns();
  }
  const std::int64_t give_up = monotonic_ns() + kMaxPaceWaitNs;
  for (;;) {
    const std::int64_t until = std::min(monotonic_ns() + kMaxSleepSliceNs, give_up);
    if (output_.wait_states_taken(until)) return;
    heartbeat_.fetch_add(1, std::memory_order_relaxed);
    if (stop_.load(std::memory_order_acquire) || monotonic_ns() >= give_up) return;
  }
}

void Loop::publish_state(bool paced) {
  if (paced) wait_for_publishers();
  const std::int64_t tick = driven_.tick();
  rigid::StateFrame* lent = config_.output_lends_frames ? output_.lend_frame() : nullptr;
  if (config_.output_lends_frames && lent == nullptr) {
    throw std::logic_error("Loop: the output was to lend the state frames and lent none");
  }
  rigid::StateFrame& frame = lent != nullptr ? *lent : frame_;
  common::fill_state_frame(driven_.world(), tick, static_cast<double>(tick) * config_.tick_dt,
                           frame);
  // The hash before the hand-over, after which the frame may hold another state's values.
  const bool hash = config_.hash_states && tick != hashed_tick_;
  const std::uint64_t h = hash ? common::state_hash(frame) : 0;
  if (lent != nullptr) {
    output_.hand_over_lent(first_arrival_ns_);
  } else {
    output_.hand_over_state(frame_, first_arrival_ns_);
  }
  if (hash) {
    common::JournalEntry entry;
    entry.tick = tick;
    entry.what = common::PublishedHash{h};
    output_.journal(entry);
    hashed_tick_ = tick;
  }
  first_arrival_ns_ = 0;
  last_publish_ns_ = monotonic_ns();
}

}  // namespace rigid::loop
