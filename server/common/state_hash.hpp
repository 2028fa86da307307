// A 64-bit fingerprint of a published state: its tick, its body count and the bit pattern of every
// per-body value (position, orientation, velocities), in order; and of a tick's contact events:
// the tick, the event count and every value of every event. rigidd journals one for each state it
// publishes and each tick with contact events; rigid-sim --replay recomputes them from its own
// world at that tick, so that "bit-identical" is checked without storing every state or event.
//
// Not cryptographic, but every step is a bijection of the running value: two states that differ in
// a single value always hash differently, and states that differ in several collide with
// probability ~2^-64. About a nanosecond per value, 13 values per body (bench/notes/
// loop-latency.md): computed on the loop thread, only when a journal is written.
#pragma once

#include <cstdint>

#include "rigid/messages.hpp"

namespace rigid::common {

std::uint64_t state_hash(const rigid::StateFrame& frame);
// stamp_ns and dropped (what the buses add) are left out: they are not the physics'.
std::uint64_t contact_hash(const rigid::ContactEvents& events);

}  // namespace rigid::common
