#include "common/journal_entry.hpp"

namespace rigid::common {

rigid::AcceptedCommand accepted_command(const JournalEntry& e) {
  rigid::AcceptedCommand a;
  a.tick = e.tick;
  if (e.kind == JournalEntry::Kind::kControl) {
    a.kind = rigid::AcceptedKind::kControl;
    a.source = e.control.source;
    a.seq = e.control.seq;
    a.command = e.control.kind;
    a.steps = e.control.steps;
    a.rtf = e.control.rtf;
    return a;
  }
  const Wrench& w = e.wrench;
  a.kind = rigid::AcceptedKind::kWrench;
  a.source = w.source;
  a.seq = w.seq;
  a.key = w.key;
  a.body_id = w.body;
  a.wrench() = w.wrench();
  a.stamp_ns = w.stamp_ns;
  return a;
}

Wrench wrench_of(const rigid::AcceptedCommand& a) {
  Wrench w;
  w.source = a.source;
  w.seq = a.seq;
  w.key = a.key;
  w.body = a.body_id;
  w.wrench() = a.wrench();
  w.stamp_ns = a.stamp_ns;
  return w;
}

}  // namespace rigid::common
