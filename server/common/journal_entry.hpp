// What the loop journals, in the order it happens: each command it accepted, with the tick at which
// it took effect, and a hash of each state it published. Fixed size and trivially copyable, so the
// loop hands entries to the journal's thread through a bounded queue without allocating
// (journal.hpp). rigid-sim --replay reads them back from the journal file and applies them to its
// own DrivenWorld at the same ticks.
//
// Timing: the loop handles commands between ticks. An entry's tick is the loop's tick counter at
// that moment: a wrench journaled at tick T acts from the step T -> T + 1; a reset or an edit at
// tick T happens before that step; a state hash at tick T is of the state after T ticks (and
// after the edits made at T before it was published); a contact hash at tick T is of the events of
// the step T - 1 -> T, journaled right after it (before that tick's state hash), for the ticks
// that have events.
#pragma once

#include <cstdint>
#include <type_traits>
#include <variant>

#include "common/applied_command.hpp"
#include "rigid/messages.hpp"

namespace rigid::common {

// state_hash() of the state published at an entry's tick.
struct PublishedHash {
  std::uint64_t hash = 0;
};

// contact_hash() of the contact events of an entry's tick, and how many there were.
struct ContactsHash {
  std::uint64_t hash = 0;
  std::int32_t events = 0;
};

struct JournalEntry {
  std::int64_t tick = 0;
  // A wrench as it entered the wrench table, a control request carried out (pause, resume, step,
  // reset, set_rtf), an edit made, a published state's hash, or a tick's contact events' hash. One
  // at a time: the journal's queue holds 16384 entries, each the size of the largest.
  std::variant<Wrench, Control, Edit, PublishedHash, ContactsHash> what;
};
static_assert(std::is_trivially_copyable_v<JournalEntry>);

// A command entry (not a hash) as the rigid/accepted message (and the journal's CommandRecord).
rigid::AcceptedCommand accepted_command(const JournalEntry& entry);
// The wrench an accepted kWrench command carries, as the loop applied it.
Wrench wrench_of(const rigid::AcceptedCommand& accepted);
// The edit an accepted kEdit command carries, as the loop made it.
Edit edit_of(const rigid::AcceptedCommand& accepted);

}  // namespace rigid::common
