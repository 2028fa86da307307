// The receiving end of one bus: runs on that transport's thread, turns each wire command into a
// validated fixed-size Command (command_validation.hpp) and queues it for the loop, never touching
// the world. Refusals are counted by reason; a refused or dropped control is answered at once.
// Undecodable payloads are counted as such.
#pragma once

#include "loop/bounded_queue.hpp"
#include "loop/command.hpp"
#include "loop/command_validation.hpp"
#include "loop/doorbell.hpp"
#include "loop/outbox.hpp"
#include "loop/reject_counters.hpp"
#include "transport/transport.hpp"

namespace rigid::loop {

class Intake final : public transport::Receiver {
 public:
  Intake(transport::Bus bus, const CommandValidator& validator, BoundedQueue<Command>& queue,
         Doorbell& doorbell, RejectCounters& rejects, ReplySink& replies)
      : bus_(bus),
        validator_(validator),
        queue_(queue),
        doorbell_(doorbell),
        rejects_(rejects),
        replies_(replies) {}

  void on_wrench(const transport::WrenchCommand& wrench) override;
  void on_control(const transport::ControlCommand& control) override;
  void on_decode_error(const transport::DecodeError& error) override;

 private:
  bool enqueue(Command& command);

  const transport::Bus bus_;
  const CommandValidator& validator_;
  BoundedQueue<Command>& queue_;
  Doorbell& doorbell_;
  RejectCounters& rejects_;
  ReplySink& replies_;
};

}  // namespace rigid::loop
