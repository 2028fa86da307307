#include "loop/journal_entry.hpp"

namespace rigid::loop {

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
  a.force = w.force;
  a.point = w.point;
  a.force_frame = w.force_frame;
  a.torque = w.torque;
  a.torque_frame = w.torque_frame;
  a.ttl = w.ttl;
  a.stamp_ns = w.stamp_ns;
  return a;
}

Wrench wrench_of(const rigid::AcceptedCommand& a) {
  Wrench w;
  w.source = a.source;
  w.seq = a.seq;
  w.key = a.key;
  w.body = a.body_id;
  w.force = a.force;
  w.point = a.point;
  w.force_frame = a.force_frame;
  w.torque = a.torque;
  w.torque_frame = a.torque_frame;
  w.ttl = a.ttl;
  w.stamp_ns = a.stamp_ns;
  return w;
}

}  // namespace rigid::loop
