// The physics world: a validated, compiled set of rigid bodies and the integrator that steps them.
//
// Constant model vs. changing data (as MuJoCo's mjModel/mjData): the constructor validates the
// WorldSpec and compiles it (world_build.cpp) into a Model, constant from then on and shared by
// the World's copies (model.hpp: the step size, the integrator, the translation coefficients, per
// motion group its parameter tables, per body its group, motion type, allowed degrees of freedom
// and spec), and a Data (data.hpp: per group its entries, each body's motion, loads and cached
// exact drift, in contiguous arrays; the pending impulses, the bodies to regroup, the guard's
// poses, the step count). Every buffer a step may need is allocated then: step() allocates
// nothing, does no I/O, reads the Model const, and gives bit-identical results for identical
// inputs, on any number of threads.
//
// Pipeline of one step (World::step, world_step.cpp):
//   1. apply the pending impulses: v += J / m, the spin by r x J where the body has the freedom,
//      its exact-drift cache made stale; then cleared;
//   2. regroup: each body whose loads started or stopped turning it since the last step moves to
//      the quiet or the loaded run of its group (each group's entries hold its quiet bodies, then
//      its loaded ones: groups.hpp), a swap with the entry at the runs' boundary;
//   3. (a world with static parts) list the bodies the contact stage looks at this step: those
//      that could reach a part within it (contact/reach.hpp: a body is next looked at when its
//      clearance and bounds on its speed and acceleration say it could touch) and those parts
//      support, except the ones held at rest; keep their motion at the step's start;
//   4. integrate: the integrator's kernel (kernels.hpp) over every group, the work cut into
//      chunks (per group a slice of each run) that the pool's threads claim (set_threads); the
//      kernel evaluates the loads (scene loads + applied loads) at every stage it needs them;
//   5. (a world with static parts) the contact stage (world_contact.cpp): for each listed body,
//      a free one checked on its own trajectory over the step keeps the kernel's state if it
//      touches nothing; otherwise, and for a supported one, the step is taken again from its start
//      split at every event (contact/contact_step.hpp: impacts located and solved, bounce series
//      summed, supports' forces, slips that stop), and the step's contact events recorded;
//   6. count the body-steps that turned by more than pi (large_rotation_steps), and the step:
//      time = step_count * dt (never accumulated, so it does not drift);
//   7. guard the slice of the bodies whose turn it is (guard_phase): each that went non-finite or
//      absurd is frozen at its last good pose, the others' poses are kept as their last good.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <thread>

#include "physics/body_motion.hpp"
#include "physics/contact/contact_event.hpp"
#include "physics/integrator.hpp"
#include "physics/spec.hpp"

namespace rigid::physics {

// A WorldSpec that cannot be simulated. `body` is the index of the body at fault and `load` the
// index of the load at fault (-1 when not about a body / a load; both -1 for the world itself),
// `field` the spec field as the scene file spells it ("mass", "inertia", "orientation",
// "integrator", "dt", "force", ...). what() is a full one-line message naming the value.
class SpecError : public std::invalid_argument {
 public:
  SpecError(int body, std::string field, const std::string& message, int load = -1)
      : std::invalid_argument(message), body_(body), load_(load), field_(std::move(field)) {}
  int body() const { return body_; }
  int load() const { return load_; }
  const std::string& field() const { return field_; }

 private:
  int body_;
  int load_;
  std::string field_;
};

// A body's state, everything expressed in the world frame, about the centre of mass.
struct BodyState {
  Vec3 p_WBo = Vec3::Zero();
  Quat q_WB = Quat::Identity();
  Vec3 v_WBo = Vec3::Zero();
  Vec3 w_WB = Vec3::Zero();
};

// Rows of every body's world-frame state, in body-id order: p_WBo (x, y, z), q_WB (w, x, y, z),
// v_WBo and w_WB, each array holding body_count() rows. Callers own the memory (a wire message, a
// NumPy buffer), so filling it allocates nothing.
struct StateRows {
  double* p_WBo;
  double* q_WB_wxyz;
  double* v_WBo;
  double* w_WB;
};

class World {
 public:
  // The most bodies a world may have (SpecError on "bodies" beyond): 2^30, ~500 GB of bodies.
  static constexpr int kMaxBodies = 1 << 30;

  // Validates the spec and compiles it. Throws SpecError naming the field and value at fault.
  explicit World(const WorldSpec& spec);
  ~World();
  World(World&&) noexcept;
  World& operator=(World&&) noexcept;
  World(const World&);
  World& operator=(const World&);

  // Advances by one step of dt(). Allocation-free.
  void step();
  void step(std::int64_t n);
  // Does ahead of the next step the work that step would do first and later steps would not:
  // the exact-drift caches (isotropic increments, axisymmetric and general free-rotor plans) of
  // the bodies nothing turns, made when a world is built, after reset() and set_state() and when
  // a body's loads stop or an impulse changes its momentum. A real-time caller runs it before its
  // first tick and after a reset, so that those ticks cost what the others do (at 10^4 general
  // bodies the first step took 7 times a later one). Moves no body and changes no result: the
  // states that follow are bit-identical with or without it. Allocation-free; on the pool's
  // threads as a step. Returns how many caches it made (0 for integrators that keep none).
  int prepare_step();

  // The threads that step the world: each motion group's bodies are split over a fixed pool,
  // created here once (no thread is created or lock taken while stepping beyond the pool's
  // hand-over). Small worlds (fewer than kMinBodiesPerThread bodies a thread) are stepped on the
  // calling thread alone. States are bit-identical for any count. n = 0: the hardware concurrency.
  // Throws std::invalid_argument for n < 0.
  static constexpr int kMinBodiesPerThread = 256;
  // A step on several threads is cut into chunks of at least kBodiesPerChunk bodies, at most
  // kChunksPerThread per thread, which the threads claim one at a time (physics/pool.hpp).
  static constexpr int kBodiesPerChunk = 256;
  static constexpr int kChunksPerThread = 32;
  void set_threads(int n);
  int threads() const;
  // The pool's worker threads (threads() - 1 of them; the caller of step() is the first thread),
  // for a caller that places threads on CPUs. Empty for one thread. set_threads and copies make
  // new workers: ask again after either.
  std::span<const std::thread::native_handle_type> worker_threads() const;
  // The next step() comes within `within_ns` (a real-time caller that knows its next deadline):
  // the pool's workers wake now and wait for it polling, so that the step does not wait for
  // their wake-up (Pool::expect_run). Nothing to do on one thread or for a world too small to be
  // split. Changes no state.
  void expect_step(std::int64_t within_ns);

  double dt() const;
  double time() const;
  std::int64_t step_count() const;
  const IntegratorInfo& integrator() const;

  int body_count() const;
  // -1 when there is no body of that name.
  int find_body(std::string_view name) const;
  // The body's spec as the world was given it (orientation normalised). Assembled on each call
  // (World keeps specs compactly: spec_store.hpp); body_name alone copies nothing.
  BodySpec body_spec(int id) const;
  std::string_view body_name(int id) const;
  // The motion group the body compiled to (body_motion.hpp), and its motion type and free degrees
  // of freedom as its spec gives them.
  BodyMotion body_motion(int id) const;
  MotionType motion_type(int id) const;
  AllowedDofs allowed_dofs(int id) const;
  // Principal moments (ascending) and the rotation from the principal frame P to B.
  Vec3 principal_moments(int id) const;
  Quat q_BP(int id) const;

  BodyState state(int id) const;
  // Every body's state(id), bit for bit, written into rows: one pass over each group's entries
  // instead of a lookup per body (the daemon's state message and Python's arrays read this).
  // A world of at least 2 kBodiesPerWriteChunk bodies is written on the step's threads
  // (set_threads) as well, in chunks of about that many: like step(), it must not run beside
  // another step() or write_states() of the same World.
  static constexpr int kBodiesPerWriteChunk = 8192;
  void write_states(const StateRows& rows) const;
  // Overwrites a body's state (kinematic constraints such as frozen axes are re-applied; a frozen
  // body is moved but stays frozen). Throws std::invalid_argument for a non-finite state.
  void set_state(int id, const BodyState& s);
  // Back to the spec's initial state, time 0, no applied loads or pending impulses.
  void reset();

  // Loads applied on top of the spec's constant loads, held until cleared: the daemon rebuilds
  // them from its table of live wrenches each tick. The point is in B, from the centre of mass.
  void clear_applied();
  // The same for one body: O(1), for callers that know which bodies they loaded.
  void clear_applied(int id);
  void add_force(int id, const Vec3& f, const Vec3& p_BoQ_B, Frame frame);
  void add_torque(int id, const Vec3& tau, Frame frame);
  // An instantaneous momentum change J (N s) at a point, applied at the start of the next step.
  void apply_impulse(int id, const Vec3& J, const Vec3& p_BoQ_B, Frame frame);

  // The guard: every kGuardEvery steps each body's state is checked, a slice of the bodies after
  // each step (so that no step pays for all of them): body id after the steps whose
  // step_count() % kGuardEvery == guard_phase(id). One that went non-finite or absurd (a
  // component beyond 1e100: a diverging scheme, e.g. explicit drag past c dt / m = 2) is put back
  // to its pose at its previous check (kGuardEvery steps before, or where the world or reset()
  // started it) and frozen there at rest: it ignores gravity, loads and impulses from then on,
  // and the rest of the world goes on. The bodies frozen so far, in the order they were frozen;
  // reset() thaws them.
  static constexpr int kGuardEvery = 64;
  std::span<const int> frozen_bodies() const;
  bool is_frozen(int id) const;
  int guard_phase(int id) const;

  // Body-steps so far in which a body turned by more than pi in one step under an integrator that
  // is not exact for large rotations (every integrator but exact_rotor and exact_rotor4): such a
  // step is a poor approximation, taken as the scheme defines it and never clamped. Reset by
  // reset().
  std::int64_t large_rotation_steps() const;

  // Diagnostics, all about the centre of mass and expressed in W.
  double kinetic_energy(int id) const;
  // Kinetic energy of every body plus the gravitational potential -m g . p of gravity-affected
  // ones.
  double total_energy() const;
  Vec3 angular_momentum_W(int id) const;

  // Static geometry (WorldSpec::planes, then ::statics): how many parts, and each one's name.
  int static_part_count() const;
  std::string_view static_part_name(int part) const;
  // The contact events of the most recent step() or step(n) call, in order of step, then body id,
  // then time (each event's time is the world's time it happened at, within its step). At most
  // kMaxContactEvents a step are kept; contact_events_dropped() counts the rest since the world
  // was made or reset. Empty for a world without static parts.
  std::span<const ContactEvent> contact_events() const;
  std::int64_t contact_events_dropped() const;
  // Body-steps whose events came faster than the contact stage resolves them one by one: the body
  // held its state over the rest of that step (contact/contact_step.hpp). Counted, never hidden.
  std::int64_t contact_capped_steps() const;
  // How parts support a body now: not at all, resting on them, sliding, or moving without slip.
  enum class Support { kFree, kResting, kSliding, kRolling };
  Support support(int id) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rigid::physics
