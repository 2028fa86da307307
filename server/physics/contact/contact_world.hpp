// What a World keeps for its contacts with static geometry: the constant half in the Model (the
// parts, each body's collision shape and surface) and the changing half in the Data (how each body
// is supported, when each is next due, the step's events). A world without static parts has
// neither: its step has no contact stage and costs what it did before contacts existed.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "physics/contact/contact_event.hpp"
#include "physics/contact/contact_step.hpp"
#include "physics/contact/static_part.hpp"
#include "physics/contact/support.hpp"
#include "physics/contact/wake_schedule.hpp"
#include "physics/groups.hpp"

namespace rigid::physics::detail {

struct ContactModel {
  // The static parts: the planes, then the shapes (WorldSpec's order), with their names.
  std::vector<contact::StaticPart> parts;
  std::vector<std::string> part_names;
  // Per body its collision shape and surface, interned (a scene has a handful of kinds).
  std::vector<contact::Convex> shapes;
  std::vector<Surface> surfaces;
  std::vector<std::int32_t> shape_of, surface_of;
  // Per body whether it takes part: dynamic bodies do; kinematic ones move on regardless and
  // nothing they meet can push them.
  std::vector<std::uint8_t> collides;

  bool enabled() const { return !parts.empty(); }
};

// The most events one step keeps (World::contact_events); beyond, they are counted as dropped.
inline constexpr int kMaxContactEvents = 4096;

struct ContactData {
  // Per body how it is supported (contact_step.hpp), and for a body settled at rest the row of its
  // translation parameters it had (its entry points at row 0, a still body's, so that the kernels
  // leave it exactly where it is at a free body's cost); -1 otherwise.
  std::vector<contact::SupportState> support;
  std::vector<std::int32_t> held_linear;
  // When each free body is next looked at (reach.hpp), and the bodies looked at every step (free
  // ones that may reach a part within a step, supported ones not settled), ascending.
  contact::WakeSchedule schedule;
  std::vector<int> watched;
  // This step's bodies for the contact stage, ascending, and their motion at the step's start
  // (capacity for every body reserved: no allocation).
  std::vector<int> active;
  std::vector<Motion> start;
  // Scratch for the next step's watched list.
  std::vector<int> next_watched;
  // The events of the last step() call, and how many did not fit in its buffer.
  std::vector<ContactEvent> events;
  std::int64_t dropped = 0;
  // Steps in which a body's events came faster than they could be resolved one by one
  // (contact_step's rounds ran out): counted, never hidden.
  std::int64_t capped = 0;
};

}  // namespace rigid::physics::detail
