#include "loop/intake.hpp"

#include <string>

#include "loop/clock.hpp"

namespace rigid::loop {

bool Intake::enqueue(Command& command) {
  command.arrival_ns = monotonic_ns();
  if (!queue_.try_push(command)) return false;
  doorbell_.ring();
  return true;
}

void Intake::on_wrench(const transport::WrenchCommand& wrench) {
  Checked<Wrench> checked = validator_.check(wrench);
  if (!checked.ok) {
    rejects_.record(checked.reason, checked.detail);
    return;
  }
  Command command;
  command.kind = Command::Kind::kWrench;
  command.bus = bus_;
  command.wrench = checked.value;
  if (!enqueue(command)) {
    rejects_.recordf(RejectReason::kQueueFull,
                     "command queue full (%zu): wrench from source %lld seq %lld dropped",
                     queue_.capacity(), static_cast<long long>(wrench.source),
                     static_cast<long long>(wrench.seq));
  }
}

void Intake::on_control(const transport::ControlCommand& control) {
  ReplyNote note = ReplyNote::kNone;
  Checked<Control> checked = validator_.check(control, &note);
  Reply reply{
      bus_, control.source, control.seq, control.command, transport::Outcome::kInvalid, 0, note, 0};
  if (!checked.ok) {
    rejects_.record(checked.reason, checked.detail);
    replies_.reply(reply);
    return;
  }
  Command command;
  command.kind = Command::Kind::kControl;
  command.bus = bus_;
  command.control = checked.value;
  if (!enqueue(command)) {
    rejects_.recordf(RejectReason::kQueueFull,
                     "command queue full (%zu): control from source %lld seq %lld dropped",
                     queue_.capacity(), static_cast<long long>(control.source),
                     static_cast<long long>(control.seq));
    reply.outcome = transport::Outcome::kFailed;
    reply.note = ReplyNote::kQueueFull;
    replies_.reply(reply);
  }
}

void Intake::on_decode_error(const transport::DecodeError& error) {
  rejects_.recordf(RejectReason::kUndecodable, "%.*s payload on %.*s (%zu bytes): %.*s",
                   static_cast<int>(to_string(error.bus).size()), to_string(error.bus).data(),
                   static_cast<int>(to_string(error.topic).size()), to_string(error.topic).data(),
                   error.payload_size, static_cast<int>(to_string(error.status).size()),
                   to_string(error.status).data());
}

}  // namespace rigid::loop
