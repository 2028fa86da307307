// What a World keeps for its contacts with static geometry: the constant half in the Model (the
// parts, each body's collision shape and surface) and the changing half in the Data (how each body
// is supported, when each is next due, the step's events). A world without static parts has
// neither: its step has no contact stage and costs what it did before contacts existed.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <tuple>
#include <vector>

#include "physics/contact/contact_event.hpp"
#include "physics/contact/contact_step.hpp"
#include "physics/contact/island_solver.hpp"
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
  // Bodies against bodies: whether any two can meet, and each body's collision group and mask.
  bool pairs = false;
  std::vector<std::uint32_t> group, mask;

  bool enabled() const { return !parts.empty() || pairs; }
  // Whether bodies a and b may collide: each one's group in the other's mask, and not two points.
  bool may_collide(int a, int b) const {
    return (group[a] & mask[b]) != 0 && (group[b] & mask[a]) != 0 &&
           !(shapes[shape_of[a]].kind == contact::Convex::Kind::kPoint &&
             shapes[shape_of[b]].kind == contact::Convex::Kind::kPoint);
  }
};

// One contact of an island at an instant (world_pairs.cpp): two bodies, or a body and a part, its
// points, normal (towards a) and gap, and the pair's surface.
struct IslandContact {
  int a = -1, b = -1, part = -1;
  Surface surface;
  Vec3 n = Vec3::UnitZ();
  std::array<Vec3, contact::kMaxFeature> p;
  int np = 0;
  double gap = 0.0;
};

// The forces a resting contact carried at its points in the last step, to start the next step's
// solve from (warm starting: a stack that rests needs the same forces step after step). Keyed by
// its bodies (or body and part); each point by where it sits on body a (in B) and its force in W.
struct WarmContact {
  int a = -1, b = -1, part = -1;
  int np = 0;
  std::array<Vec3, contact::kMaxFeature> p_B;
  std::array<Vec3, contact::kMaxFeature> f_W;
  auto key() const { return std::tuple(a, b, part); }
};

// A body's bounding box over the broad phase's look-ahead, in the frame falling with gravity.
struct SweptBox {
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();
};

// The broad phase's shortest and longest look-ahead, in steps (world_pairs.cpp).
inline constexpr int kMinLookAhead = 16;
inline constexpr int kMaxLookAhead = 1024;

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
  // Where one body's contact step writes its events before they join `events` (kMaxContactEvents
  // long, sized once: growing `events` to its capacity for each body would clear it each time).
  std::vector<ContactEvent> scratch;
  std::int64_t dropped = 0;
  // Steps in which a body's events came faster than they could be resolved one by one
  // (contact_step's rounds ran out): counted, never hidden.
  std::int64_t capped = 0;

  // --- bodies against bodies (world_pairs.cpp) ---
  // The broad phase: the bodies' swept boxes, the order sweep and prune keeps them in (by lo.x,
  // sorted again from the last order), the pairs whose boxes overlap (a < b) and when it runs next
  // (a change of a body's loads or state runs it at the next step).
  std::vector<SweptBox> boxes;
  std::vector<int> order;
  std::vector<std::pair<int, int>> candidates;
  std::int64_t next_broad = 0;
  // The steps the next run looks ahead over: doubled after each run that found no pair (bodies
  // far apart pay for the broad phase ever more rarely), back to the shortest once one does, or a
  // body's loads or state change.
  int look_ahead = kMinLookAhead;
  // This step's pairs that may touch within it, the islands they join bodies into (union-find
  // roots per body, -1 outside any), and the islands' bodies grouped by root.
  std::vector<std::pair<int, int>> close;
  std::vector<int> root;
  std::vector<int> island_ids;
  // Scratch for an island's solve.
  std::vector<contact::IslandBody> ibodies;
  std::vector<contact::IslandRow> irows;
  std::vector<int> ilocal;  // per body id its index in the island being solved, -1 otherwise
  // Last step's contact forces, sorted by key, and this step's being written.
  std::vector<WarmContact> warm, next_warm;
  // Sleep: per body the steps it has been calm in a row, and the group it sleeps in (-1: awake).
  std::vector<std::uint16_t> calm;
  std::vector<int> sleep_group;
};

}  // namespace rigid::physics::detail
