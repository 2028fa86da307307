#include "loop/publisher.hpp"

#include <string>

#include "loop/clock.hpp"

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

std::string_view outcome_name(rigid::Outcome outcome) {
  switch (outcome) {
    case rigid::Outcome::kOk:
      return "ok";
    case rigid::Outcome::kInvalid:
      return "invalid";
    case rigid::Outcome::kNotAllowed:
      return "not allowed";
    case rigid::Outcome::kFailed:
      return "failed";
  }
  return "?";
}

}  // namespace

Publisher::Publisher(transport::Transport& transport, const rigid::StateFrame& shape, Log& log,
                     std::size_t reply_capacity)
    : transport_(transport), log_(log), states_(Snapshot{shape, 0}), replies_(reply_capacity) {}

Publisher::~Publisher() {
  stop();
}

void Publisher::start() {
  thread_ = std::thread([this] { run(); });
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
  states_.back().frame = frame;
  publish_back(command_arrival_ns);
}

void Publisher::hand_over(rigid::StateFrame& frame, std::int64_t command_arrival_ns) {
  std::swap(states_.back().frame, frame);  // swaps the vectors' buffers: no copy, no allocation
  publish_back(command_arrival_ns);
}

void Publisher::publish_back(std::int64_t command_arrival_ns) {
  Snapshot& back = states_.back();
  // A command whose state was skipped first shows in this one.
  back.command_arrival_ns = command_arrival_ns == 0 || (carried_arrival_ns_ != 0 &&
                                                        carried_arrival_ns_ < command_arrival_ns)
                                ? carried_arrival_ns_
                                : command_arrival_ns;
  carried_arrival_ns_ = 0;
  if (states_.publish()) {
    states_skipped_.fetch_add(1, std::memory_order_relaxed);
    // back() is now the snapshot that was never sent.
    carried_arrival_ns_ = states_.back().command_arrival_ns;
  }
  wake();
}

bool Publisher::wait_taken(std::int64_t deadline_ns) {
  for (;;) {
    const std::uint32_t seen = taken_.count();
    if (!states_.pending()) return true;
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
        "control " + std::string(kind_name(r.kind)) + " from source " + std::to_string(r.source) +
        " seq " + std::to_string(r.seq) + " (" + std::string(to_string(transport_.bus())) +
        "): " + std::string(outcome_name(r.outcome)) + " at tick " + std::to_string(r.tick);
    if (!m.message.empty()) line += ": " + m.message;
    if (result != transport::PublishResult::kOk) line += " (the reply could not be sent)";
    log_.line(line);
  }
}

void Publisher::run() {
  for (;;) {
    const std::uint32_t seen = work_.load(std::memory_order_acquire);
    // Read before the take: a stop requested after the last offer then still sends that state
    // (read after, a state offered while the previous one was being sent was dropped at exit).
    const bool stopping = stop_.load(std::memory_order_acquire);
    // The state first: a client that gets a step's reply finds its state already sent.
    if (Snapshot* snapshot = states_.take()) {
      taken_.ring();  // a loop waiting to hand over the next state may go on
      snapshot->frame.stamp_ns = realtime_ns();
      if (transport_.publish(snapshot->frame) == transport::PublishResult::kOk) {
        states_sent_.fetch_add(1, std::memory_order_relaxed);
        if (snapshot->command_arrival_ns != 0) {
          command_to_state_.record(monotonic_ns() - snapshot->command_arrival_ns);
        }
      } else if (!logged_send_failure_) {
        logged_send_failure_ = true;
        log_.line("cannot publish the state on " + std::string(to_string(transport_.bus())) +
                  " (further failures are counted in Stats)");
      }
    }
    send_replies();
    if (stopping) return;
    work_.wait(seen, std::memory_order_acquire);
  }
}

}  // namespace rigid::loop
