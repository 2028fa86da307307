#include "common/journal_entry.hpp"

namespace rigid::common {

rigid::AcceptedCommand accepted_command(const JournalEntry& e) {
  rigid::AcceptedCommand a;
  a.tick = e.tick;
  if (const Control* k = std::get_if<Control>(&e.what)) {
    a.kind = rigid::AcceptedKind::kControl;
    a.source = k->source;
    a.seq = k->seq;
    a.command = k->kind;
    a.steps = k->steps;
    a.rtf = k->rtf;
    return a;
  }
  if (const Edit* d = std::get_if<Edit>(&e.what)) {
    a.kind = rigid::AcceptedKind::kEdit;
    a.source = d->source;
    a.seq = d->seq;
    a.body_id = d->body;
    a.edit = d->kind;
    a.state_edit() = d->state_edit();
    a.stamp_ns = d->stamp_ns;
    return a;
  }
  if (const Wrench* w = std::get_if<Wrench>(&e.what)) {
    a.kind = rigid::AcceptedKind::kWrench;
    a.source = w->source;
    a.seq = w->seq;
    a.key = w->key;
    a.body_id = w->body;
    a.wrench() = w->wrench();
    a.stamp_ns = w->stamp_ns;
  }
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

Edit edit_of(const rigid::AcceptedCommand& a) {
  Edit d;
  d.source = a.source;
  d.seq = a.seq;
  d.kind = a.edit;
  d.body = a.body_id;
  d.state_edit() = a.state_edit();
  d.stamp_ns = a.stamp_ns;
  return d;
}

}  // namespace rigid::common
