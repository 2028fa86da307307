// What the loop journals, in the order it happens: each command it accepted, with the tick at which
// it took effect, and a hash of each state it published. Fixed size and trivially copyable, so the
// loop hands entries to the journal's thread through a bounded queue without allocating
// (journal.hpp). rigid-sim --replay reads them back from the journal file and applies them to its
// own DrivenWorld at the same ticks.
//
// Timing: the loop handles commands between ticks. An entry's tick is the loop's tick counter at
// that moment: a wrench journaled at tick T acts from the step T -> T + 1; a reset at tick T
// happens before that step; a state hash at tick T is of the state after T ticks; a contact hash
// at tick T is of the events of the step T - 1 -> T, journaled right after it (before that tick's
// state hash), for the ticks that have events.
#pragma once

#include <cstdint>
#include <type_traits>

#include "common/applied_command.hpp"
#include "rigid/messages.hpp"

namespace rigid::common {

struct JournalEntry {
  enum class Kind : std::uint8_t { kWrench, kControl, kStateHash, kContactHash };
  Kind kind = Kind::kWrench;
  std::int64_t tick = 0;
  Wrench wrench;            // kWrench: as it entered the wrench table
  Control control;          // kControl: a request carried out (pause, resume, step, reset, set_rtf)
  std::uint64_t hash = 0;   // kStateHash: state_hash() of the state published at `tick`;
                            // kContactHash: contact_hash() of the contact events of `tick`
  std::int32_t events = 0;  // kContactHash: how many
};
static_assert(std::is_trivially_copyable_v<JournalEntry>);

// A command entry as the rigid/accepted message (and the journal's CommandRecord).
rigid::AcceptedCommand accepted_command(const JournalEntry& entry);
// The wrench an accepted kWrench command carries, as the loop applied it.
Wrench wrench_of(const rigid::AcceptedCommand& accepted);

}  // namespace rigid::common
