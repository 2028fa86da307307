// The receiving end of one bus: runs on that transport's thread, turns each wire command into a
// validated fixed-size Command (command_validation.hpp) and queues it for the loop, never touching
// the world. In order, a command must come from a permitted sender (with DDS Security: an
// authenticated identity, and for a wrench the body its writer's partition names; controls and
// edits only while controls are on), be within its sender's share of the command rate
// (sender_rates.hpp), and pass validation. Refusals are counted by reason and by sender; a refused
// control or edit is answered at once (a refusal for permission or rate at a bounded rate per
// sender), a refused wrench at a bounded rate per sender. Undecodable payloads are counted as
// such.
#pragma once

#include <cstdint>
#include <string_view>

#include "loop/bounded_queue.hpp"
#include "loop/command.hpp"
#include "loop/command_validation.hpp"
#include "loop/doorbell.hpp"
#include "loop/outbox.hpp"
#include "loop/reject_counters.hpp"
#include "loop/sender_rates.hpp"
#include "transport/transport.hpp"

namespace rigid::loop {

struct IntakePolicy {
  bool controls = true;                 // rigidd --controls on|off (plain buses)
  bool secure = false;                  // DDS Security: only authenticated identities' commands
  double commands_per_second = 2000.0;  // per sender (scene limits.max_commands_per_second)
};

// The sender of a command from its origin on `bus` (Sender::key and a printable name).
Sender sender_of(rigid::Bus bus, const transport::Origin& origin);
// 0 without security, else a hash of the identity.
std::uint64_t owner_of(const transport::Origin& origin);

class Intake final : public transport::Receiver {
 public:
  Intake(rigid::Bus bus, const CommandValidator& validator, const IntakePolicy& policy,
         BoundedQueue<Command>& queue, Doorbell& doorbell, RejectCounters& rejects,
         ReplySink& replies);

  void on_wrench(const rigid::WrenchCommand& wrench, const transport::Origin& origin) override;
  void on_control(const rigid::ControlCommand& control, const transport::Origin& origin) override;
  void on_edit(const rigid::EditCommand& edit, const transport::Origin& origin) override;
  void on_decode_error(const transport::DecodeError& error) override;

 private:
  bool enqueue(Command& command);
  bool admit_privileged(const Sender& sender, const transport::Origin& origin,
                        std::string_view what, std::int64_t source, std::int64_t seq, Reply& reply);
  void refuse_wrench(const rigid::WrenchCommand& wrench, const Sender& sender, RejectReason reason,
                     const std::string& detail);

  const rigid::Bus bus_;
  const CommandValidator& validator_;
  const IntakePolicy policy_;
  BoundedQueue<Command>& queue_;
  Doorbell& doorbell_;
  RejectCounters& rejects_;
  ReplySink& replies_;
  SenderRates rates_;
};

// Answers a refused wrench on its bus if its sender has replies left this second.
void answer_refused_wrench(ReplySink& replies, RejectCounters& rejects, rigid::Bus bus,
                           std::int64_t source, std::int64_t seq, const Sender& sender,
                           std::string_view why, std::int64_t tick);

}  // namespace rigid::loop
