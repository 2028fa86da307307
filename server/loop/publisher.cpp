#include "loop/publisher.hpp"

#include <pthread.h>
#include <sched.h>

#include <cstdio>
#include <cstring>
#include <ctime>
#include <string>

#include "common/state_conversion.hpp"
#include "loop/clock.hpp"
#include "rigid/names.hpp"
#include "util/thread_name.hpp"

namespace rigid::loop {
namespace {

std::string_view kind_name(rigid::ControlKind kind) {
  switch (kind) {
    case rigid::ControlKind::kPause:
      return "pause";
    case rigid::ControlKind::kResume:
      return "resume";
    case rigid::ControlKind::kStep:
      return "step";
    case rigid::ControlKind::kReset:
      return "reset";
    case rigid::ControlKind::kSetRtf:
      return "set_rtf";
    case rigid::ControlKind::kNone:
      break;
  }
  return "unknown";
}

}  // namespace

Publisher::Publisher(transport::Transport& transport, SharedStates& states, Log& log,
                     std::size_t reply_capacity, bool contacts)
    : transport_(transport),
      log_(log),
      states_(states),
      reader_(states.add_reader()),
      replies_(reply_capacity) {
  if (contacts) {
    contacts_ = std::make_unique<ContactOutbox>();
    common::reserve_contact_events(contact_message_);
  }
}

Publisher::Publisher(transport::Transport& transport, const rigid::StateFrame& shape, Log& log,
                     std::size_t reply_capacity)
    : transport_(transport),
      log_(log),
      own_states_(std::make_unique<SharedStates>(shape)),
      states_(*own_states_),
      reader_(states_.add_reader()),
      replies_(reply_capacity) {}

Publisher::~Publisher() {
  stop();
}

void Publisher::start() {
  thread_ = std::thread([this] { run(); });
  util::name_thread(thread_, "rigid-pub-" + std::string(to_string(transport_.bus())));
}

void Publisher::stop() {
  if (!thread_.joinable()) return;
  stop_.store(true, std::memory_order_release);
  wake();
  thread_.join();
}

void Publisher::wake() {
  work_.fetch_add(1, std::memory_order_release);
  work_.notify_one();
}

void Publisher::offer(const rigid::StateFrame& frame, std::int64_t command_arrival_ns) {
  offer_slot(states_.put_copied(frame, 1), command_arrival_ns);
}

void Publisher::hand_over(rigid::StateFrame& frame, std::int64_t command_arrival_ns) {
  offer_slot(states_.put_swapped(frame, 1), command_arrival_ns);
}

void Publisher::offer_slot(int slot, std::int64_t command_arrival_ns) {
  // A command whose state was skipped first shows in this one.
  states_.set_arrival(slot, reader_,
                      command_arrival_ns == 0 ||
                              (carried_arrival_ns_ != 0 && carried_arrival_ns_ < command_arrival_ns)
                          ? carried_arrival_ns_
                          : command_arrival_ns);
  carried_arrival_ns_ = 0;
  // Release: the slot's frame, stamp and arrival before the publisher's acquire.
  const std::uint32_t old =
      mailbox_.exchange(static_cast<std::uint32_t>(slot) | kFresh, std::memory_order_acq_rel);
  if ((old & kFresh) != 0) {
    // Never taken: this publisher's hold on it goes, and its command's arrival to the next state.
    const int skipped = static_cast<int>(old & ~kFresh);
    states_skipped_.fetch_add(1, std::memory_order_relaxed);
    carried_arrival_ns_ = states_.arrival(skipped, reader_);
    states_.release(skipped);
  }
  wake();
}

bool Publisher::wait_taken(std::int64_t deadline_ns) {
  for (;;) {
    const std::uint32_t seen = taken_.count();
    if ((mailbox_.load(std::memory_order_acquire) & kFresh) == 0) return true;
    if (monotonic_ns() >= deadline_ns) return false;
    taken_.wait_until(seen, deadline_ns);
  }
}

bool Publisher::reply(const Reply& reply) {
  if (!replies_.try_push(reply)) {
    replies_dropped_.fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  wake();
  return true;
}

bool Publisher::offer_contacts(const rigid::ContactEvents& events, std::int64_t stamp_ns) {
  if (contacts_ == nullptr || !contacts_->put(events, stamp_ns)) {
    contact_events_lost_.fetch_add(static_cast<std::int64_t>(events.event_count()),
                                   std::memory_order_relaxed);
    return false;
  }
  wake();
  return true;
}

bool Publisher::wait_contacts_room(std::size_t events, std::int64_t deadline_ns) {
  if (contacts_ == nullptr) return true;
  for (;;) {
    const std::uint32_t seen = taken_.count();
    if (contacts_->has_room(events)) return true;
    if (monotonic_ns() >= deadline_ns) return false;
    taken_.wait_until(seen, deadline_ns);
  }
}

void Publisher::send_contacts() {
  if (contacts_ == nullptr) return;
  bool took = false;
  while (contacts_->take(contact_message_)) {
    took = true;
    // What the physics could not keep (the loop's count) and what this bus lost so far.
    contact_message_.dropped += contact_events_lost_.load(std::memory_order_relaxed);
    const transport::PublishResult result = transport_.publish(contact_message_);
    if (result == transport::PublishResult::kOk) {
      contacts_sent_.fetch_add(1, std::memory_order_relaxed);
      continue;
    }
    contact_events_lost_.fetch_add(static_cast<std::int64_t>(contact_message_.event_count()),
                                   std::memory_order_relaxed);
    if (!logged_contact_failure_) {
      logged_contact_failure_ = true;
      log_.line("cannot publish contact events on " + std::string(to_string(transport_.bus())) +
                (result == transport::PublishResult::kNotPermitted
                     ? ": this identity may not publish rigid/contacts (a keystore made before it: "
                       "rigid-keys add KEYSTORE rigidd --may serve --force, and init again for the "
                       "governance); further events are counted as lost"
                     : " (further failures are counted as lost events)"));
    }
  }
  if (took) taken_.ring();  // a loop waiting for room may go on
}

void Publisher::send_replies() {
  Reply r;
  while (replies_.try_pop(r)) {
    rigid::ControlReply m;
    m.source = r.source;
    m.seq = r.seq;
    m.command = r.kind;
    m.outcome = r.outcome;
    m.tick = r.tick;
    m.message = reply_message(r);
    const transport::PublishResult result = transport_.publish(m);
    std::string line =
        (r.kind == rigid::kReplyToEdit ? "edit " + std::string(rigid::edit_name(r.edit))
                                       : "control " + std::string(kind_name(r.kind))) +
        " from source " + std::to_string(r.source) + " seq " + std::to_string(r.seq) + " (" +
        std::string(to_string(transport_.bus())) +
        "): " + std::string(rigid::outcome_name(r.outcome)) + " at tick " + std::to_string(r.tick);
    if (!m.message.empty()) line += ": " + m.message;
    if (result != transport::PublishResult::kOk) line += " (the reply could not be sent)";
    if (r.kind == rigid::kReplyToEdit) {
      const std::int64_t now = monotonic_ns();
      if (now - edit_window_ns_ >= 1'000'000'000) {
        if (edit_lines_left_out_ > 0) {
          log_.line(std::to_string(edit_lines_left_out_) +
                    " more edit answers in the last second, not logged");
        }
        edit_window_ns_ = now;
        edit_lines_ = 0;
        edit_lines_left_out_ = 0;
      }
      if (++edit_lines_ > kEditLinesPerSecond) {
        ++edit_lines_left_out_;
        continue;
      }
    }
    log_.line(line);
  }
}

void Publisher::send_state() {
  // Takes the mailbox's slot, leaving it without kFresh (the writer's exchange never mistakes it
  // for an offer not taken).
  const std::uint32_t m = mailbox_.fetch_and(~kFresh, std::memory_order_acq_rel);
  if ((m & kFresh) == 0) return;
  taken_.ring();  // a loop waiting to hand over the next state may go on
  const int slot = static_cast<int>(m & ~kFresh);
  const std::int64_t arrival_ns = states_.arrival(slot, reader_);
  if (transport_.publish(states_.frame(slot)) == transport::PublishResult::kOk) {
    states_sent_.fetch_add(1, std::memory_order_relaxed);
    if (arrival_ns != 0) command_to_state_.record(monotonic_ns() - arrival_ns);
  } else if (!logged_send_failure_) {
    logged_send_failure_ = true;
    log_.line("cannot publish the state on " + std::string(to_string(transport_.bus())) +
              " (further failures are counted in Stats)");
  }
  states_.release(slot);  // last: the frame may be refilled once every reader let go
}

void Publisher::run() {
  for (;;) {
    const std::uint32_t seen = work_.load(std::memory_order_acquire);
    // Read before the take: a stop requested after the last offer then still sends that state
    // (read after, a state offered while the previous one was being sent was dropped at exit).
    const bool stopping = stop_.load(std::memory_order_acquire);
    // The contact events first, then the state: a client that gets a state has the events of
    // its tick; and the state before the replies: a client that gets a step's reply finds its
    // state already sent.
    send_contacts();
    send_state();
    send_replies();
    if (const int priority = realtime_priority_.load(std::memory_order_acquire); priority > 0)
      mind_realtime_share(priority);
    if (stopping) return;
    work_.wait(seen, std::memory_order_acquire);
  }
}

void Publisher::watch_realtime_share(int priority) {
  realtime_priority_.store(priority, std::memory_order_release);
  wake();  // the window starts now, not at the next state
}

void Publisher::mind_realtime_share(int priority) {
  timespec cpu{};
  if (clock_gettime(CLOCK_THREAD_CPUTIME_ID, &cpu) != 0) return;
  const std::int64_t cpu_ns = std::int64_t{cpu.tv_sec} * 1'000'000'000 + cpu.tv_nsec;
  const RealtimeShare::Change change = realtime_share_.update(cpu_ns, monotonic_ns());
  if (change == RealtimeShare::Change::kNone) return;
  const bool down = change == RealtimeShare::Change::kStepDown;
  if (down) priority_step_downs_.fetch_add(1, std::memory_order_relaxed);
  sched_param param{};
  param.sched_priority = down ? 0 : priority;
  const int error = pthread_setschedparam(pthread_self(), down ? SCHED_OTHER : SCHED_FIFO, &param);
  // A publisher whose load comes and goes could change every few seconds for hours.
  constexpr int kMaxLogged = 10;
  if (priority_changes_logged_ > kMaxLogged) return;
  ++priority_changes_logged_;
  char percent[16];
  std::snprintf(percent, sizeof percent, "%.0f%%", 100.0 * realtime_share_.last_share());
  std::string line = "publisher " + std::string(to_string(transport_.bus())) + ": took " + percent +
                     " of a CPU over the last second";
  if (error != 0) {
    line += std::string(", but could not change its priority (") + std::strerror(error) + ")";
  } else if (down) {
    line += " at real-time priority, more than " + std::to_string(int(kRealtimeLimit * 100)) +
            "%: at normal priority until it takes less than " +
            std::to_string(int(kRealtimeResume * 100)) +
            "%, so that the loop's CPU keeps time for its other threads";
  } else {
    line += ": back at SCHED_FIFO priority " + std::to_string(priority);
  }
  if (priority_changes_logged_ > kMaxLogged) line += " (further changes are not logged)";
  log_.line(line);
}

}  // namespace rigid::loop
