// One body's step among static parts: its motion over the step, split at every event.
//
// A free body follows its own trajectory until it first touches a part (time_of_impact.hpp):
// the step is split there, the impulses at every touching point are solved together
// (point_solver.hpp: restitution along the normal, Coulomb friction, through the points' K
// matrices), and the rest of the step goes on from that instant. A body whose normal speed an
// impact leaves at zero is supported: its contact forces are solved from its accelerations (the
// same laws one derivative down) and held over the rest of the step, which is split again where a
// slip stops, another feature or part is touched, or the supports let go. Where the forces are
// constant (a body sliding or resting on a face, a sphere slipping or rolling), this is the exact
// motion; where the body turns on its supports it is first order, its supports' drift taken back
// and its energy never allowed to rise.
//
// A bounce with restitution e < 1 that would repeat within the step is summed in closed form:
// after an impact leaving normal speed u under normal acceleration -g_n, the bounces take
// 2 u / (g_n (1 - e)) in all (a geometric series), so the body is supported from there on: it
// comes to rest in finite time, at the time the series gives, with no speed threshold to tune.
#pragma once

#include <array>
#include <cstdint>
#include <span>

#include "physics/contact/contact_event.hpp"
#include "physics/contact/moving_body.hpp"
#include "physics/contact/static_part.hpp"
#include "physics/contact/support.hpp"

namespace rigid::physics::contact {

// How a body is supported, kept from step to step.
struct SupportState {
  enum class Phase : std::uint8_t { kFree, kResting, kSliding, kRolling };
  Phase phase = Phase::kFree;
  // Resting and nothing has changed since: the body does not move this step and costs nothing.
  // The World clears it when the body's loads, state or momentum change.
  bool settled = false;
};

// Where a step's events go: a fixed buffer (no allocation while stepping); events past its end
// are counted, not kept.
class EventSink {
 public:
  EventSink(ContactEvent* buffer, int capacity) : buffer_(buffer), capacity_(capacity) {}
  void push(const ContactEvent& e) {
    if (size_ < capacity_) {
      buffer_[size_++] = e;
    } else {
      ++dropped_;
    }
  }
  int size() const { return size_; }
  std::int64_t dropped() const { return dropped_; }
  void clear() { size_ = 0; }

 private:
  ContactEvent* buffer_;
  int capacity_;
  int size_ = 0;
  std::int64_t dropped_ = 0;
};

// The body being stepped and what it may touch.
struct ContactBody {
  std::int32_t id = 0;
  const Convex* shape = nullptr;
  Surface surface;
  // Parts it may reach within the step (indices into `parts`).
  std::span<const std::int32_t> candidates;
};

struct ContactStepResult {
  int rounds = 0;       // events handled
  bool capped = false;  // the step ran out of rounds (the rest taken without further events)
};

// Steps the body by dt from its state at the step's start among `parts`.
ContactStepResult contact_step(MovingBody& body, const ContactBody& cb,
                               std::span<const StaticPart> parts, double dt, SupportState& st,
                               EventSink& events);

// Speeds below this (m/s) are round-off: a support slipping this slowly sticks, a body moving this
// slowly on its supports is at rest.
inline constexpr double kStillSpeed = 1e-10;

}  // namespace rigid::physics::contact
