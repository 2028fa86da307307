// What happened at a contact during a step, for everyone downstream (the buses, recordings, the
// view, Python): an impact or a change of how a body is supported.
#pragma once

#include <cstdint>
#include <string_view>

#include "physics/math.hpp"

namespace rigid::physics {

enum class ContactEventKind : std::uint8_t {
  kImpact,    // an impulse where a body touched a part (impulse: the impulse on the body)
  kResting,   // the body starts resting on its supports: no velocity, held by them
  kSliding,   // the body starts sliding on its supports (it moves with slip at a contact)
  kRolling,   // the body starts moving on its supports without slip at any contact
  kSeparate,  // the body leaves its supports: in free flight from here
};
std::string_view to_string(ContactEventKind k);

struct ContactEvent {
  ContactEventKind kind = ContactEventKind::kImpact;
  std::int32_t body = 0;          // body id
  std::int32_t part = 0;          // static part index (planes first, then shapes), or -1: a body
  std::int32_t other = -1;        // the other body's id for a contact between bodies, else -1
  double time = 0.0;              // within the step: the world's time at the step's start plus this
  Vec3 p_W = Vec3::Zero();        // where (the impulse's centre for an impact)
  Vec3 n_W = Vec3::UnitZ();       // the part's (or the other body's) normal there, towards the body
  Vec3 impulse_W = Vec3::Zero();  // on the body (N s); zero for the transitions
};

}  // namespace rigid::physics
