// Random values for every rigid message, reproducible from a seed: every field set, numbers over
// the whole finite range of their type, enumerations including values outside the named ones.
#pragma once

#include <bit>
#include <cstdint>
#include <random>
#include <string>

#include "rigid/messages.hpp"

namespace rigid::transport::testing {

class RandomMessages {
 public:
  explicit RandomMessages(std::uint64_t seed) : rng_(seed) {}

  // Any finite double, from subnormals to the largest, either sign: random bits, with the
  // exponent of infinities and NaNs replaced (those are tested separately, bit for bit).
  double real() {
    std::uint64_t bits = rng_();
    if (((bits >> 52) & 0x7ff) == 0x7ff) bits &= ~(std::uint64_t{1} << 62);
    return std::bit_cast<double>(bits);
  }
  std::int64_t i64() { return static_cast<std::int64_t>(rng_()); }
  std::int32_t i32() { return static_cast<std::int32_t>(rng_()); }
  std::size_t below(std::size_t n) { return static_cast<std::size_t>(rng_() % n); }
  // Bytes 1..255: any C string (NUL ends one).
  std::string text(std::size_t max_length = 40) {
    std::string s(below(max_length + 1), ' ');
    for (char& c : s)
      c = static_cast<char>(1 + below(255));
    return s;
  }
  Vec3 vec3() { return {real(), real(), real()}; }
  template <class Enum>
  Enum any_enum() {
    return static_cast<Enum>(below(4) == 0 ? i32() : static_cast<std::int32_t>(below(6)));
  }

  StateFrame state(std::size_t bodies) {
    StateFrame m;
    m.tick = i64();
    m.sim_time = real();
    m.stamp_ns = i64();
    m.resize(bodies);
    for (auto& x : m.ids)
      x = i32();
    for (auto& x : m.position)
      x = real();
    for (auto& x : m.orientation)
      x = real();
    for (auto& x : m.linear_velocity)
      x = real();
    for (auto& x : m.angular_velocity)
      x = real();
    return m;
  }

  WrenchCommand wrench() {
    WrenchCommand m;
    m.source = i64();
    m.seq = i64();
    m.key = i32();
    m.body_id = i32();
    m.body_name = text();
    m.force = vec3();
    m.point = vec3();
    m.force_frame = any_enum<Frame>();
    m.torque = vec3();
    m.torque_frame = any_enum<Frame>();
    m.ttl = real();
    m.stamp_ns = i64();
    return m;
  }

  // Every field of a state edit (whatever the kind: the wire carries them all).
  void fill(StateEdit& m) {
    m.set = i32();
    m.position = vec3();
    m.orientation = {real(), real(), real(), real()};
    m.linear_velocity = vec3();
    m.velocity_frame = any_enum<Frame>();
    m.angular_velocity = vec3();
    m.angular_velocity_frame = any_enum<Frame>();
  }

  EditCommand edit() {
    EditCommand m;
    m.source = i64();
    m.seq = i64();
    m.kind = any_enum<EditKind>();
    m.body_id = i32();
    m.body_name = text();
    fill(m);
    m.stamp_ns = i64();
    return m;
  }

  AcceptedCommand accepted() {
    AcceptedCommand m;
    m.tick = i64();
    m.kind = any_enum<AcceptedKind>();
    m.source = i64();
    m.seq = i64();
    m.key = i32();
    m.body_id = i32();
    m.force = vec3();
    m.point = vec3();
    m.force_frame = any_enum<Frame>();
    m.torque = vec3();
    m.torque_frame = any_enum<Frame>();
    m.ttl = real();
    m.command = any_enum<ControlKind>();
    m.steps = i64();
    m.rtf = real();
    m.edit = any_enum<EditKind>();
    fill(m);
    m.stamp_ns = i64();
    return m;
  }

  ControlCommand control() {
    ControlCommand m;
    m.source = i64();
    m.seq = i64();
    m.command = any_enum<ControlKind>();
    m.steps = i64();
    m.rtf = real();
    return m;
  }

  ControlReply reply() {
    ControlReply m;
    m.source = i64();
    m.seq = i64();
    m.command = any_enum<ControlKind>();
    m.outcome = any_enum<Outcome>();
    m.tick = i64();
    m.message = text(200);
    return m;
  }

  StatsReport stats() {
    StatsReport m;
    m.tick = i64();
    m.sim_time = real();
    m.mode = any_enum<Mode>();
    m.paused = below(2) == 1;
    m.rtf_last_second = real();
    m.rtf_since_start = real();
    m.lateness_p50_us = real();
    m.lateness_p99_us = real();
    m.lateness_max_us = real();
    m.overruns = i64();
    m.step_cost_p50_us = real();
    m.step_cost_max_us = real();
    m.bodies_frozen = i64();
    m.large_rotation_steps = i64();
    m.states_skipped = i64();
    m.commands_accepted = i64();
    m.rejected = {i64(), i64(), i64(), i64(), i64(), i64(), i64()};
    m.dds = {i64(), i64(), i64(), i64()};
    m.lcm = {i64(), i64(), i64(), i64()};
    return m;
  }

  // With `parts` static parts (by default a few, so that every round trip carries some).
  SceneDescription scene(std::size_t bodies) { return scene(bodies, below(6)); }
  SceneDescription scene(std::size_t bodies, std::size_t parts) {
    SceneDescription m;
    m.scene_name = text();
    m.dt = real();
    m.substeps = i32();
    m.publish_every = i32();
    m.gravity = vec3();
    m.integrator = text();
    m.max_force = real();
    m.max_torque = real();
    for (std::size_t i = 0; i < bodies; ++i) {
      m.ids.push_back(i32());
      m.names.push_back(text());
      m.masses.push_back(real());
      for (int k = 0; k < 6; ++k)
        m.inertia.push_back(real());
      m.shape_kinds.push_back(any_enum<ShapeKind>());
      for (int k = 0; k < 3; ++k)
        m.shape_dims.push_back(real());
    }
    for (std::size_t i = 0; i < parts; ++i) {
      m.part_names.push_back(text());
      m.part_kinds.push_back(any_enum<ShapeKind>());
      for (int k = 0; k < 3; ++k)
        m.part_position.push_back(real());
      for (int k = 0; k < 4; ++k)
        m.part_orientation.push_back(real());
      for (int k = 0; k < 3; ++k)
        m.part_dims.push_back(real());
      m.part_restitution.push_back(real());
      m.part_friction.push_back(real());
    }
    return m;
  }

  ContactEvents contacts(std::size_t events) {
    ContactEvents m;
    m.tick = i64();
    m.sim_time = real();
    m.stamp_ns = i64();
    m.dropped = i64();
    m.resize(events);
    for (auto& x : m.kinds)
      x = any_enum<ContactKind>();
    for (auto& x : m.bodies)
      x = i32();
    for (auto& x : m.parts)
      x = i32();
    for (auto& x : m.times)
      x = real();
    for (auto& x : m.position)
      x = real();
    for (auto& x : m.normal)
      x = real();
    for (auto& x : m.impulse)
      x = real();
    return m;
  }

 private:
  std::mt19937_64 rng_;
};

}  // namespace rigid::transport::testing
