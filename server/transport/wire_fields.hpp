// Each message's fields, written once for both buses and both directions. The types idlc generates
// from msgs/rigid.idl and lcm-gen from msgs/rigid.lcm name their fields as the plain messages
// (rigid/messages.hpp) do, so one list per message serves both; what differs between the buses is
// how a string or a sequence is held (a fixed char array and a C sequence on DDS, std::string and
// std::vector on LCM), and Encoder and Decoder handle either by the wire field's type.
//
// fields(io, plain, wire, n) visits every field: io(plain_field, wire_field) copies one value,
// io.array(plain_vector, wire_sequence, count) a per-body array of `count` elements, and
// io.column(plain_vector, member, wire_sequence, count) one member of each element of a vector
// of structs. n is the message's row count (bodies; refused sources for StatsReport; events for
// ContactEvents; bodies and static parts for SceneDescription: SceneRows), which the bus adapter
// checked against its lengths before decoding. The count fields only LCM has (num_bodies, ...) are
// the LCM adapter's to set and check.
//
// Adding a field: add it to the message (messages.hpp), to msgs/rigid.idl and msgs/rigid.lcm under
// the same name (one IDL allows: its keywords, and names that differ from another only in case,
// are not), and to its list here. Adding a message: its list here, then one entry per bus
// (dds_convert.hpp, lcm_convert.hpp) and per codec.
//
// Only the bus adapters include this (it is instantiated with their generated types).
#pragma once

#include <algorithm>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <iterator>
#include <string>
#include <type_traits>
#include <vector>

#include "rigid/messages.hpp"

namespace rigid::transport::wire {

template <class T, class U>
concept Is = std::same_as<std::remove_const_t<T>, U>;

// A Cyclone DDS sequence (idlc's C binding).
template <class S>
concept CSequence = requires(S s) {
  s._buffer;
  s._length;
  s._maximum;
  s._release;
};

// The element of a plain vector a column reads: the element itself, or one of its members.
struct Whole {
  template <class T>
  T& operator()(T& element) const {
    return element;
  }
};
template <class Member>
struct Field {
  Member member;
  template <class T>
  decltype(auto) operator()(T& element) const {
    return element.*member;
  }
};
template <class Member>
Field(Member) -> Field<Member>;  // clang before 17 deduces no aggregate's arguments

// Storage that encoding to DDS needs where a plain value cannot be lent as it is (strings as fixed
// char arrays, enumerations as int32): one buffer per such column of a message, grown when a
// larger message comes and then reused, so that encoding allocates nothing in the steady state.
// One per writer (per message type); not shared between threads.
class Scratch {
 public:
  void rewind() { next_ = 0; }
  template <class T>
  T* take(std::size_t count) {
    // Byte storage (whose allocation implicitly creates the trivially copyable T objects written
    // into it), aligned as operator new aligns it.
    static_assert(std::is_trivially_copyable_v<T> &&
                  alignof(T) <= __STDCPP_DEFAULT_NEW_ALIGNMENT__);
    if (next_ == buffers_.size()) buffers_.emplace_back();
    std::vector<std::byte>& b = buffers_[next_++];
    if (b.size() < count * sizeof(T)) b.resize(count * sizeof(T));
    return reinterpret_cast<T*>(b.data());
  }

 private:
  std::vector<std::vector<std::byte>> buffers_;
  std::size_t next_ = 0;
};

// Plain -> wire. On DDS, per-body arrays of the same element type are lent, not copied: the wire
// sample points into the plain message, which must outlive the write (dds_write serializes before
// it returns). ok turns false when a string does not fit its bound (DDS string<N>).
class Encoder {
 public:
  explicit Encoder(Scratch* scratch = nullptr) : scratch_(scratch) {
    if (scratch_ != nullptr) scratch_->rewind();
  }
  bool ok = true;

  template <class P, class W>
  void operator()(const P& in, W& out) {
    if constexpr (std::is_enum_v<P> || std::is_arithmetic_v<P>) {
      out = static_cast<W>(in);
    } else if constexpr (Is<P, Vec3> || Is<P, std::array<double, 4>>) {
      std::copy(in.begin(), in.end(), std::begin(out));
    } else if constexpr (Is<P, std::string> && std::is_array_v<W>) {
      ok = put_string(in, out) && ok;
    } else {
      out = in;
    }
  }

  template <class T, class S>
  void array(const std::vector<T>& in, S& out, std::size_t count) {
    column(in, Whole{}, out, count);
  }

  template <class T, class Get, class S>
  void column(const std::vector<T>& in, Get get, S& out, std::size_t count) {
    if constexpr (CSequence<S>) {
      using Elem = std::remove_pointer_t<decltype(out._buffer)>;
      using Value = std::remove_cvref_t<decltype(get(in[0]))>;
      Elem* data = nullptr;
      if constexpr (std::is_same_v<Get, Whole> && std::is_same_v<Value, Elem>) {
        // The writer only reads the buffer, so lending a const vector's storage is safe.
        data = const_cast<Elem*>(in.data());
      } else {
        data = scratch_->take<Elem>(count);
        for (std::size_t i = 0; i < count; ++i)
          (*this)(get(in[i]), data[i]);
      }
      out._maximum = static_cast<std::uint32_t>(count);
      out._length = out._maximum;
      out._buffer = data;
      out._release = false;  // Cyclone does not own it
    } else if constexpr (std::is_same_v<Get, Whole> && std::is_same_v<T, typename S::value_type>) {
      out.assign(in.begin(), in.begin() + static_cast<std::ptrdiff_t>(count));
    } else {
      out.resize(count);
      for (std::size_t i = 0; i < count; ++i)
        (*this)(get(in[i]), out[i]);
    }
  }

 private:
  // Bounded IDL strings are fixed arrays in the C binding (string<N> is char[N + 1]). A string that
  // does not fit is refused rather than cut.
  template <std::size_t N>
  static bool put_string(const std::string& in, char (&out)[N]) {
    if (in.size() >= N) return false;
    std::copy(in.begin(), in.end(), out);
    out[in.size()] = '\0';
    return true;
  }

  Scratch* scratch_;
};

// Wire -> plain, reusing the plain message's storage.
class Decoder {
 public:
  template <class P, class W>
  void operator()(P& out, const W& in) {
    if constexpr (std::is_enum_v<P> || std::is_arithmetic_v<P>) {
      out = static_cast<P>(in);
    } else if constexpr (Is<P, Vec3> || Is<P, std::array<double, 4>>) {
      std::copy(std::begin(in), std::end(in), out.begin());
    } else if constexpr (Is<P, std::string> && std::is_array_v<W>) {
      out.assign(in, strnlen(in, std::extent_v<W>));
    } else {
      out = in;
    }
  }

  // Exactly `count` elements: lcm-gen's decoder leaves an array untouched when its count is 0, so a
  // reused message may hold a previous message's elements past the count.
  template <class T, class S>
  void array(std::vector<T>& out, const S& in, std::size_t count) {
    if constexpr (CSequence<S>) {
      using Elem = std::remove_pointer_t<decltype(in._buffer)>;
      if constexpr (std::is_same_v<T, Elem>) {
        if (count == 0 || in._buffer == nullptr) {
          out.clear();
        } else {
          out.assign(in._buffer, in._buffer + count);
        }
        return;
      }
    } else if constexpr (std::is_same_v<T, typename S::value_type>) {
      out.assign(in.begin(), in.begin() + static_cast<std::ptrdiff_t>(count));
      return;
    }
    column(out, Whole{}, in, count);
  }

  template <class T, class Get, class S>
  void column(std::vector<T>& out, Get get, const S& in, std::size_t count) {
    out.resize(count);
    for (std::size_t i = 0; i < count; ++i) {
      if constexpr (CSequence<S>) {
        (*this)(get(out[i]), in._buffer[i]);
      } else {
        (*this)(get(out[i]), in[i]);
      }
    }
  }
};

// The rows of a SceneDescription: it has two kinds, bodies and static parts.
struct SceneRows {
  std::size_t bodies = 0;
  std::size_t parts = 0;
};

// The type of a message's row count.
template <class P>
struct RowsOf {
  using type = std::size_t;
};
template <>
struct RowsOf<SceneDescription> {
  using type = SceneRows;
};

// ---- The field lists. ----

template <class IO, class P, class W>
void wrench_fields(IO& io, P& m, W& w) {
  io(m.force, w.force);
  io(m.point, w.point);
  io(m.force_frame, w.force_frame);
  io(m.torque, w.torque);
  io(m.torque_frame, w.torque_frame);
  io(m.ttl, w.ttl);
}

template <class IO, class P, class W>
void state_edit_fields(IO& io, P& m, W& w) {
  io(m.set, w.parts);  // (`set` is a keyword of IDL 4)
  io(m.position, w.position);
  io(m.orientation, w.orientation);
  io(m.linear_velocity, w.linear_velocity);
  io(m.velocity_frame, w.velocity_frame);
  io(m.angular_velocity, w.angular_velocity);
  io(m.angular_velocity_frame, w.angular_velocity_frame);
}

template <class IO, Is<StateFrame> P, class W>
void fields(IO& io, P& m, W& w, std::size_t n) {
  io(m.tick, w.tick);
  io(m.sim_time, w.sim_time);
  io(m.stamp_ns, w.stamp_ns);
  io.array(m.ids, w.ids, n);
  io.array(m.position, w.position, 3 * n);
  io.array(m.orientation, w.orientation, 4 * n);
  io.array(m.linear_velocity, w.linear_velocity, 3 * n);
  io.array(m.angular_velocity, w.angular_velocity, 3 * n);
}

template <class IO, Is<WrenchCommand> P, class W>
void fields(IO& io, P& m, W& w, std::size_t /*n*/) {
  io(m.source, w.source);
  io(m.seq, w.seq);
  io(m.key, w.key);
  io(m.body_id, w.body_id);
  io(m.body_name, w.body_name);
  wrench_fields(io, m, w);
  io(m.stamp_ns, w.stamp_ns);
}

template <class IO, Is<ControlCommand> P, class W>
void fields(IO& io, P& m, W& w, std::size_t /*n*/) {
  io(m.source, w.source);
  io(m.seq, w.seq);
  io(m.command, w.command);
  io(m.steps, w.steps);
  io(m.rtf, w.rtf);
}

template <class IO, Is<EditCommand> P, class W>
void fields(IO& io, P& m, W& w, std::size_t /*n*/) {
  io(m.source, w.source);
  io(m.seq, w.seq);
  io(m.kind, w.kind);
  io(m.body_id, w.body_id);
  io(m.body_name, w.body_name);
  state_edit_fields(io, m, w);
  io(m.stamp_ns, w.stamp_ns);
}

template <class IO, Is<ControlReply> P, class W>
void fields(IO& io, P& m, W& w, std::size_t /*n*/) {
  io(m.source, w.source);
  io(m.seq, w.seq);
  io(m.command, w.command);
  io(m.outcome, w.outcome);
  io(m.tick, w.tick);
  io(m.message, w.message);
}

template <class IO, Is<RejectCounts> P, class W>
void fields(IO& io, P& m, W& w, std::size_t /*n*/) {
  io(m.non_finite, w.non_finite);
  io(m.unknown_body, w.unknown_body);
  io(m.over_limit, w.over_limit);
  io(m.undecodable, w.undecodable);
  io(m.stale_sequence, w.stale_sequence);
  io(m.queue_full, w.queue_full);
  io(m.invalid, w.invalid);
  io(m.over_share, w.over_share);
  io(m.rate_limited, w.rate_limited);
  io(m.not_permitted, w.not_permitted);
}

template <class IO, Is<TransportCounts> P, class W>
void fields(IO& io, P& m, W& w, std::size_t /*n*/) {
  io(m.sent, w.sent);
  io(m.send_failures, w.send_failures);
  io(m.received, w.received);
  io(m.decode_failures, w.decode_failures);
}

// n: the number of refused sources.
template <class IO, Is<StatsReport> P, class W>
void fields(IO& io, P& m, W& w, std::size_t n) {
  io(m.tick, w.tick);
  io(m.sim_time, w.sim_time);
  io(m.mode, w.mode);
  io(m.paused, w.paused);
  io(m.rtf_last_second, w.rtf_last_second);
  io(m.rtf_since_start, w.rtf_since_start);
  io(m.lateness_p50_us, w.lateness_p50_us);
  io(m.lateness_p99_us, w.lateness_p99_us);
  io(m.lateness_max_us, w.lateness_max_us);
  io(m.overruns, w.overruns);
  io(m.step_cost_p50_us, w.step_cost_p50_us);
  io(m.step_cost_max_us, w.step_cost_max_us);
  io(m.bodies_frozen, w.bodies_frozen);
  io(m.large_rotation_steps, w.large_rotation_steps);
  io(m.states_skipped, w.states_skipped);
  io(m.commands_accepted, w.commands_accepted);
  fields(io, m.rejected, w.rejected, 0);
  fields(io, m.dds, w.dds, 0);
  fields(io, m.lcm, w.lcm, 0);
  io.column(m.refused_by_source, Field{&SourceRefusals::sender}, w.refused_sender, n);
  io.column(m.refused_by_source, Field{&SourceRefusals::count}, w.refused_count, n);
  io.column(m.refused_by_source, Field{&SourceRefusals::last_reason}, w.refused_last_reason, n);
}

template <class IO, Is<SceneDescription> P, class W>
void fields(IO& io, P& m, W& w, const SceneRows& rows) {
  const std::size_t n = rows.bodies;
  const std::size_t parts = rows.parts;
  io(m.scene_name, w.scene_name);
  io(m.dt, w.dt);
  io(m.substeps, w.substeps);
  io(m.publish_every, w.publish_every);
  io(m.gravity, w.gravity);
  io(m.integrator, w.integrator);
  io(m.max_force, w.max_force);
  io(m.max_torque, w.max_torque);
  io(m.max_ttl, w.max_ttl);
  io(m.max_wrenches_per_source, w.max_wrenches_per_source);
  io(m.max_commands_per_second, w.max_commands_per_second);
  io.array(m.ids, w.ids, n);
  io.array(m.names, w.names, n);
  io.array(m.masses, w.masses, n);
  io.array(m.inertia, w.inertia, 6 * n);
  io.array(m.shape_kinds, w.shape_kinds, n);
  io.array(m.shape_dims, w.shape_dims, 3 * n);
  io.array(m.part_names, w.part_names, parts);
  io.array(m.part_kinds, w.part_kinds, parts);
  io.array(m.part_position, w.part_position, 3 * parts);
  io.array(m.part_orientation, w.part_orientation, 4 * parts);
  io.array(m.part_dims, w.part_dims, 3 * parts);
  io.array(m.part_restitution, w.part_restitution, parts);
  io.array(m.part_friction, w.part_friction, parts);
}

// n: the number of events.
template <class IO, Is<ContactEvents> P, class W>
void fields(IO& io, P& m, W& w, std::size_t n) {
  io(m.tick, w.tick);
  io(m.sim_time, w.sim_time);
  io(m.stamp_ns, w.stamp_ns);
  io(m.dropped, w.dropped);
  io.array(m.kinds, w.kinds, n);
  io.array(m.bodies, w.bodies, n);
  io.array(m.parts, w.parts, n);
  io.array(m.times, w.times, n);
  io.array(m.position, w.position, 3 * n);
  io.array(m.normal, w.normal, 3 * n);
  io.array(m.impulse, w.impulse, 3 * n);
}

template <class IO, Is<AcceptedCommand> P, class W>
void fields(IO& io, P& m, W& w, std::size_t /*n*/) {
  io(m.tick, w.tick);
  io(m.kind, w.kind);
  io(m.source, w.source);
  io(m.seq, w.seq);
  io(m.key, w.key);
  io(m.body_id, w.body_id);
  wrench_fields(io, m, w);
  io(m.command, w.command);
  io(m.steps, w.steps);
  io(m.rtf, w.rtf);
  io(m.edit, w.edit_kind);  // (IDL names ignore case: `edit` is the struct Edit)
  state_edit_fields(io, m, w);
  io(m.stamp_ns, w.stamp_ns);
}

// ---- Both directions, for a message whose row count the caller knows. ----

// The rows a plain message has, or false if its per-body arrays disagree or exceed the bounds.
inline bool rows(const StateFrame& m, std::size_t& n) {
  n = m.body_count();
  return m.lengths_agree() && n <= kMaxBodies;
}
inline bool rows(const SceneDescription& m, SceneRows& n) {
  n = {m.body_count(), m.part_count()};
  return m.lengths_agree() && n.bodies <= kMaxBodies && n.parts <= kMaxParts;
}
inline bool rows(const ContactEvents& m, std::size_t& n) {
  n = m.event_count();
  return m.lengths_agree() && n <= kMaxContactEvents;
}
inline bool rows(const StatsReport& m, std::size_t& n) {
  n = m.refused_by_source.size();
  return n <= kMaxRefusedSources;
}
template <class P>
bool rows(const P& /*m*/, std::size_t& n) {
  n = 0;
  return true;
}

template <class P, class W, class N>
bool encode(const P& m, W& w, const N& n, Scratch* scratch = nullptr) {
  Encoder io(scratch);
  fields(io, m, w, n);
  return io.ok;
}

template <class W, class P, class N>
void decode(const W& w, P& m, const N& n) {
  Decoder io;
  fields(io, m, w, n);
}

}  // namespace rigid::transport::wire
