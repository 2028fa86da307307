#include "loop/loop.hpp"

#include <sys/prctl.h>

#include <algorithm>

#include "loop/clock.hpp"
#include "loop/state_conversion.hpp"

namespace rigid::loop {
namespace {

using transport::ControlKind;
using transport::Mode;
using transport::Outcome;

constexpr std::int64_t kMaxSleepSliceNs = 100'000'000;  // stop requests are seen within this
constexpr std::int64_t kIdleRepublishNs = 1'000'000'000;

// Tells the CPU this is a spin-wait (saves power, frees the sibling hyper-thread).
inline void cpu_relax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#endif
}

physics::Vec3 eigen(const Vec3& v) {
  return {v[0], v[1], v[2]};
}

physics::Frame frame_of(transport::Frame f) {
  return f == transport::Frame::kBody ? physics::Frame::kBody : physics::Frame::kWorld;
}

}  // namespace

Loop::Loop(const physics::WorldSpec& spec, const LoopConfig& config,
           BoundedQueue<Command>& commands, Doorbell& doorbell, RejectCounters& rejects,
           LoopOutput& output)
    : world_(spec),
      config_(config),
      commands_(commands),
      doorbell_(doorbell),
      rejects_(rejects),
      output_(output),
      wrenches_(config.wrench_capacity),
      wrench_sources_(config.source_capacity),
      control_sources_(config.source_capacity),
      schedule_(0, config.tick_dt * 1e9),
      stats_(config.tick_dt, 0),
      summaries_(LoopSummary{}) {
  shape_state_frame(world_, frame_);
  paused_ = config_.mode == Mode::kLockstep;
  loaded_.reserve(static_cast<std::size_t>(world_.body_count()));
  is_loaded_.assign(static_cast<std::size_t>(world_.body_count()), 0);
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
    const std::int64_t now = monotonic_ns();
    if (stats_.window_due(now)) roll_stats(now);
  }
}

bool Loop::sleep_to(std::int64_t deadline_ns) {
  const std::int64_t wake = deadline_ns - config_.spin_ns;
  for (;;) {
    if (stop_.load(std::memory_order_acquire)) return false;
    const std::int64_t now = monotonic_ns();
    if (now >= wake) break;
    sleep_until(std::min(wake, now + kMaxSleepSliceNs));
  }
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
  }
  if (!wants_tick() && now - last_publish_ns_ >= kIdleRepublishNs) publish_state();
  if (stats_.window_due(now)) roll_stats(now);
}

void Loop::roll_stats(std::int64_t now_ns) {
  summaries_.back() =
      stats_.close_window(now_ns, tick_, static_cast<double>(tick_) * config_.tick_dt, config_.mode,
                          paused_ && step_left_ == 0);
  summaries_.publish();
}

void Loop::drain() {
  // At most one queue's worth per pass: producers refilling the queue as fast as it empties
  // cannot keep the loop from ticking.
  Command c;
  for (std::size_t n = commands_.capacity(); n > 0 && commands_.try_pop(c); --n)
    handle(c);
}

void Loop::handle(const Command& c) {
  if (c.kind == Command::Kind::kWrench) {
    handle_wrench(c.wrench, c.arrival_ns);
  } else {
    handle_control(c);
  }
}

void Loop::handle_wrench(const Wrench& w, std::int64_t arrival_ns) {
  std::int64_t last = 0;
  if (!wrench_sources_.accept(w.source, w.seq, &last)) {
    rejects_.recordf(RejectReason::kStaleSequence,
                     "wrench from source %lld: seq %lld is not above the source's last %lld",
                     static_cast<long long>(w.source), static_cast<long long>(w.seq),
                     static_cast<long long>(last));
    return;
  }
  const std::int64_t expires = tick_ + ticks_to_live(w.ttl, config_.tick_dt);
  if (wrenches_.upsert(w, expires) == WrenchTable::Upsert::kFull) {
    rejects_.recordf(RejectReason::kQueueFull,
                     "wrench table full (%zu live wrenches): wrench from source %lld seq %lld "
                     "dropped",
                     wrenches_.capacity(), static_cast<long long>(w.source),
                     static_cast<long long>(w.seq));
    return;
  }
  accepted_.fetch_add(1, std::memory_order_relaxed);
  new_command_ = true;
  if (first_arrival_ns_ == 0) first_arrival_ns_ = arrival_ns;
}

void Loop::answer(const Command& c, Outcome outcome, ReplyNote note, std::int64_t detail) {
  output_.reply(
      Reply{c.bus, c.control.source, c.control.seq, c.control.kind, outcome, tick_, note, detail});
}

void Loop::handle_control(const Command& c) {
  const Control& k = c.control;
  std::int64_t last = 0;
  if (!control_sources_.accept(k.source, k.seq, &last)) {
    rejects_.recordf(RejectReason::kStaleSequence,
                     "control from source %lld: seq %lld is not above the source's last %lld",
                     static_cast<long long>(k.source), static_cast<long long>(k.seq),
                     static_cast<long long>(last));
    answer(c, Outcome::kInvalid, ReplyNote::kStaleSequence, last);
    return;
  }
  accepted_.fetch_add(1, std::memory_order_relaxed);
  const bool lockstep = config_.mode == Mode::kLockstep;
  switch (k.kind) {
    case ControlKind::kPause:
    case ControlKind::kResume:
      if (lockstep) {
        answer(c, Outcome::kNotAllowed, ReplyNote::kLockstepOnlySteps);
        return;
      }
      paused_ = k.kind == ControlKind::kPause;
      answer(c, Outcome::kOk);
      return;
    case ControlKind::kStep:
      if (!paused_) {
        answer(c, Outcome::kNotAllowed, ReplyNote::kStepNeedsPause);
      } else if (step_left_ > 0) {
        answer(c, Outcome::kNotAllowed, ReplyNote::kStepInProgress, step_left_);
      } else {
        // Answered when the last of its ticks is done (step_tick).
        step_left_ = k.steps;
        step_total_ = k.steps;
        step_request_ = c;
      }
      return;
    case ControlKind::kReset:
      do_reset();
      answer(c, Outcome::kOk);
      return;
    case ControlKind::kSetRtf:
      if (config_.mode != Mode::kRealtime) {
        answer(c, Outcome::kNotAllowed, ReplyNote::kRtfNeedsRealtime);
        return;
      }
      rtf_ = k.rtf;
      on_schedule_ = false;  // the next tick starts a schedule with the new period
      answer(c, Outcome::kOk);
      return;
    case ControlKind::kNone:
      break;
  }
  // The intake lets only known commands through; answer anyway rather than stay silent.
  answer(c, Outcome::kInvalid, ReplyNote::kUnknownCommand);
}

void Loop::do_reset() {
  if (step_left_ > 0) {
    const std::int64_t done = step_total_ - step_left_;
    step_left_ = 0;
    output_.reply(Reply{step_request_.bus, step_request_.control.source, step_request_.control.seq,
                        ControlKind::kStep, Outcome::kFailed, tick_, ReplyNote::kInterruptedByReset,
                        done});
  }
  world_.reset();  // also clears the applied loads
  wrenches_.clear();
  for (const int id : loaded_)
    is_loaded_[static_cast<std::size_t>(id)] = 0;
  loaded_.clear();
  new_command_ = false;
  first_arrival_ns_ = 0;
  tick_ = 0;
  on_schedule_ = false;
  publish_state();
}

void Loop::step_tick() {
  const std::int64_t t0 = monotonic_ns();
  // Rebuild the applied loads from the live wrenches: clear the bodies loaded last time (only
  // those), then load the live wrenches in arrival order (deterministic), remembering their bodies.
  if (wrenches_.size() > 0 || !loaded_.empty()) {
    for (const int id : loaded_) {
      world_.clear_applied(id);
      is_loaded_[static_cast<std::size_t>(id)] = 0;
    }
    loaded_.clear();
    for (const ActiveWrench& e : wrenches_.active()) {
      const Wrench& w = e.wrench;
      world_.add_force(w.body, eigen(w.force), eigen(w.point), frame_of(w.force_frame));
      if (w.torque[0] != 0.0 || w.torque[1] != 0.0 || w.torque[2] != 0.0) {
        world_.add_torque(w.body, eigen(w.torque), frame_of(w.torque_frame));
      }
      if (!is_loaded_[static_cast<std::size_t>(w.body)]) {
        is_loaded_[static_cast<std::size_t>(w.body)] = 1;
        loaded_.push_back(w.body);  // within the capacity reserved for every body: no allocation
      }
    }
  }
  world_.step(config_.substeps);
  ++tick_;
  stats_.count_tick();
  wrenches_.expire(tick_);
  stats_.record_step_cost(monotonic_ns() - t0);

  bool publish = tick_ % config_.publish_every == 0 || new_command_;
  new_command_ = false;
  bool step_done = false;
  if (step_left_ > 0 && --step_left_ == 0) {
    publish = true;  // a stepping controller needs the state its step ended on
    step_done = true;
  }
  if (publish) publish_state();
  if (step_done) {
    output_.reply(Reply{step_request_.bus, step_request_.control.source, step_request_.control.seq,
                        ControlKind::kStep, Outcome::kOk, tick_, ReplyNote::kNone, step_total_});
  }
}

void Loop::publish_state() {
  fill_state_frame(world_, tick_, static_cast<double>(tick_) * config_.tick_dt, frame_);
  output_.offer_state(frame_, first_arrival_ns_);
  first_arrival_ns_ = 0;
  last_publish_ns_ = monotonic_ns();
}

}  // namespace rigid::loop
