#include "protocol.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include "rigid/client/names.hpp"

namespace rigid::view {
namespace {

// (Bytes as the host has them: the hosts rigid runs on are little-endian, x86-64 and aarch64.)
void put_f64s(std::string& out, const double* v, std::size_t n) {
  out.append(reinterpret_cast<const char*>(v), n * sizeof(double));
}
void put_f32s(std::string& out, const float* v, std::size_t n) {
  out.append(reinterpret_cast<const char*>(v), n * sizeof(float));
}
// v's bytes at out[at], inside out (the fields of a frame's fixed parts, at their offsets in
// protocol.hpp: the page reads them at the same ones).
template <typename T>
void put_at(std::string& out, std::size_t at, const T& v) {
  std::memcpy(out.data() + at, &v, sizeof v);
}

void number(std::string& out, double v) {
  if (!std::isfinite(v)) {
    out += "null";
    return;
  }
  char b[32];
  std::snprintf(b, sizeof b, "%.17g", v);
  out += b;
}
void integer(std::string& out, std::int64_t v) {
  out += std::to_string(v);
}
void string(std::string& out, std::string_view s) {
  out += '"';
  for (const char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (u < 0x20) {
      char b[8];
      std::snprintf(b, sizeof b, "\\u%04x", u);
      out += b;
    } else {
      out += c;
    }
  }
  out += '"';
}
void numbers(std::string& out, const double* v, std::size_t n) {
  out += '[';
  for (std::size_t i = 0; i < n; ++i) {
    if (i) out += ',';
    number(out, v[i]);
  }
  out += ']';
}

// A strict reader of one flat JSON object: string keys and values without escapes, numbers,
// arrays of up to four numbers (a quaternion). Anything else is refused.
class Reader {
 public:
  explicit Reader(std::string_view s) : s_(s) {}
  struct Value {
    enum class Kind { kString, kNumber, kArray } kind = Kind::kNumber;
    std::string_view text;
    double num = 0;
    std::vector<double> array;
  };
  // Calls field(key, value) for each member; returns an error or "".
  template <typename F>
  std::string object(F&& field) {
    ws();
    if (!eat('{')) return "expected a JSON object";
    ws();
    if (eat('}')) return end();
    for (int members = 0;; ++members) {
      if (members >= 8) return "too many fields";
      std::string_view key;
      if (!str(key)) return "expected a field name";
      ws();
      if (!eat(':')) return "expected ':'";
      ws();
      Value v;
      if (peek() == '"') {
        v.kind = Value::Kind::kString;
        if (!str(v.text)) return "bad string";
      } else if (peek() == '[') {
        v.kind = Value::Kind::kArray;
        ++i_;
        ws();
        if (!eat(']')) {
          for (;;) {
            double d;
            if (v.array.size() >= 4 || !num(d)) return "bad array (at most 4 numbers)";
            v.array.push_back(d);
            ws();
            if (eat(']')) break;
            if (!eat(',')) return "bad array";
            ws();
          }
        }
      } else if (!num(v.num)) {
        return "bad value of " + std::string(key.substr(0, 24));
      }
      if (std::string e = field(key, v); !e.empty()) return e;
      ws();
      if (eat('}')) return end();
      if (!eat(',')) return "expected ',' or '}'";
      ws();
    }
  }

 private:
  char peek() const { return i_ < s_.size() ? s_[i_] : '\0'; }
  bool eat(char c) {
    if (peek() != c) return false;
    ++i_;
    return true;
  }
  void ws() {
    while (i_ < s_.size() && (s_[i_] == ' ' || s_[i_] == '\n' || s_[i_] == '\t' || s_[i_] == '\r'))
      ++i_;
  }
  std::string end() {
    ws();
    return i_ == s_.size() ? "" : "trailing bytes after the object";
  }
  bool str(std::string_view& out) {
    if (!eat('"')) return false;
    const std::size_t start = i_;
    while (i_ < s_.size() && s_[i_] != '"') {
      const auto u = static_cast<unsigned char>(s_[i_]);
      if (s_[i_] == '\\' || u < 0x20 || u >= 0x80) return false;
      ++i_;
    }
    if (i_ >= s_.size()) return false;
    out = s_.substr(start, i_ - start);
    ++i_;
    return out.size() <= 32;
  }
  bool num(double& out) {
    const std::size_t start = i_;
    while (i_ < s_.size() && std::strchr("+-0123456789.eE", s_[i_]) != nullptr)
      ++i_;
    if (i_ == start || i_ - start > 32) return false;
    const std::string text(s_.substr(start, i_ - start));
    char* end = nullptr;
    out = std::strtod(text.c_str(), &end);
    return end == text.c_str() + text.size() && std::isfinite(out);
  }

  std::string_view s_;
  std::size_t i_ = 0;
};

bool whole(double v, double lo, double hi) {
  return v >= lo && v <= hi && std::floor(v) == v;
}

}  // namespace

bool state_in_float32(std::size_t bodies) {
  return bodies > kExactStateMaxBodies;
}

namespace {

// The header both frames share (protocol.hpp), for n bodies.
void put_state_header(std::string& out, const StateFrame& state, std::size_t n,
                      std::uint32_t scene_generation, std::uint32_t flags) {
  static_assert(kStateStampAt + sizeof(std::int64_t) == kStateHeaderBytes);
  const std::size_t at = out.size();
  out.resize(at + kStateHeaderBytes, '\0');
  put_at(out, at, kStateMagic);
  put_at(out, at + kStateBodiesAt, static_cast<std::uint32_t>(n));
  put_at(out, at + kStateGenerationAt, scene_generation);
  put_at(out, at + kStateFlagsAt, flags);
  put_at(out, at + kStateTickAt, state.tick);  // (i64, f64, i64: as StateFrame has them)
  put_at(out, at + kStateSimTimeAt, state.sim_time);
  put_at(out, at + kStateStampAt, state.stamp_ns);
}

// A per-body array of n bodies at its place, as f32 or f64; a short one (a decoder guarantees
// they are not) is padded with zeros. `narrow`: scratch for the f32 copy.
void put_real_array(std::string& out, const std::vector<double>& v, std::size_t per_body,
                    std::size_t n, bool f32, std::vector<float>& narrow) {
  const std::size_t at = out.size(), have = std::min(v.size(), per_body * n);
  if (f32) {
    narrow.assign(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(have));
    put_f32s(out, narrow.data(), have);
    out.resize(at + per_body * n * sizeof(float), '\0');
  } else {
    put_f64s(out, v.data(), have);
    out.resize(at + per_body * n * sizeof(double), '\0');
  }
}

}  // namespace

std::string encode_state(const StateFrame& state, std::uint32_t scene_generation,
                         const std::vector<float>& energy_drift,
                         const std::vector<float>& momentum_drift) {
  const std::size_t n = state.ids.size();
  const bool f32 = state_in_float32(n);
  std::string out;
  out.reserve(kStateHeaderBytes + state_bytes_per_body(n) * n);
  put_state_header(out, state, n, scene_generation, f32 ? kStateFloat32 : 0);
  std::vector<float> narrow;
  const auto array = [&](const std::vector<double>& v, std::size_t per_body) {
    put_real_array(out, v, per_body, n, f32, narrow);
  };
  array(state.position, 3);
  array(state.orientation, 4);
  array(state.linear_velocity, 3);
  array(state.angular_velocity, 3);
  for (const std::vector<float>* drift : {&energy_drift, &momentum_drift}) {
    const std::size_t at = out.size();
    put_f32s(out, drift->data(), std::min(drift->size(), n));
    out.resize(at + n * sizeof(float), '\0');
  }
  out.append(reinterpret_cast<const char*>(state.ids.data()), n * sizeof(std::int32_t));
  return out;
}

std::string encode_pose_state(const StateFrame& state, std::uint32_t scene_generation,
                              const std::vector<float>& energy_drift,
                              const std::vector<float>& momentum_drift,
                              const std::vector<std::int32_t>& watched) {
  const std::size_t n = state.ids.size();
  const std::size_t k = std::min(watched.size(), kMaxWatched);
  std::string out;
  out.reserve(pose_state_bytes(n, k));
  put_state_header(out, state, n, scene_generation, kStatePoses);
  std::vector<float> narrow;
  static_assert(kPoseBytesPerBody == (3 + 4) * sizeof(float) + sizeof(std::int32_t));
  put_real_array(out, state.position, 3, n, true, narrow);
  put_real_array(out, state.orientation, 4, n, true, narrow);
  out.append(reinterpret_cast<const char*>(state.ids.data()), n * sizeof(std::int32_t));
  // The worst drifts, as the page's DriftTable.worst() finds them in a whole frame: the largest
  // value above 0 (NaN never wins), its slot, -1 when none.
  static_assert(kPoseWatchedCountAt + 2 * sizeof(std::uint32_t) == kPoseTrailerBytes);
  const std::size_t trailer = out.size();
  out.resize(trailer + kPoseTrailerBytes, '\0');  // (its last 4 bytes: 0, aligning the records)
  const auto put_worst = [&](const std::vector<float>& drift, std::size_t value_at,
                             std::size_t slot_at) {
    float worst = 0;
    std::int32_t at = -1;
    for (std::size_t i = 0; i < std::min(drift.size(), n); ++i) {
      if (drift[i] > worst) {
        worst = drift[i];
        at = static_cast<std::int32_t>(i);
      }
    }
    put_at(out, trailer + value_at, worst);
    put_at(out, trailer + slot_at, at);
  };
  put_worst(energy_drift, kPoseWorstEnergyAt, kPoseWorstEnergySlotAt);
  put_worst(momentum_drift, kPoseWorstMomentumAt, kPoseWorstMomentumSlotAt);
  std::uint32_t records = 0;
  const auto real = [](const std::vector<double>& v, std::size_t i) {
    return i < v.size() ? v[i] : 0.0;
  };
  for (std::size_t w = 0; w < k; ++w) {
    const auto it = std::find(state.ids.begin(), state.ids.end(), watched[w]);
    if (it == state.ids.end()) continue;
    const auto slot = static_cast<std::size_t>(it - state.ids.begin());
    const std::size_t record = out.size();
    out.resize(record + kWatchedRecordBytes, '\0');
    put_at(out, record, static_cast<std::int32_t>(slot));
    put_at(out, record + kWatchedEnergyAt, slot < energy_drift.size() ? energy_drift[slot] : 0.0f);
    put_at(out, record + kWatchedMomentumAt,
           slot < momentum_drift.size() ? momentum_drift[slot] : 0.0f);
    std::array<double, 13> values{};
    static_assert(kWatchedStateAt + sizeof values == kWatchedRecordBytes);
    for (std::size_t c = 0; c < 3; ++c) {
      values[c] = real(state.position, 3 * slot + c);
      values[7 + c] = real(state.linear_velocity, 3 * slot + c);
      values[10 + c] = real(state.angular_velocity, 3 * slot + c);
    }
    for (std::size_t c = 0; c < 4; ++c)
      values[3 + c] = real(state.orientation, 4 * slot + c);
    put_at(out, record + kWatchedStateAt, values);
    ++records;
  }
  put_at(out, trailer + kPoseWatchedCountAt, records);
  return out;
}

MomentBox box_of_moments(double mass, const double* in) {
  MomentBox box;
  Eigen::Matrix3d inertia;
  inertia << in[0], in[3], in[4], in[3], in[1], in[5], in[4], in[5], in[2];
  if (!(mass > 0) || !inertia.allFinite() || inertia.norm() <= 0) {
    box.size = {0.1, 0.1, 0.1};  // a point mass: a small marker
    return box;
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(inertia);
  const Eigen::Vector3d m = solver.eigenvalues();
  Eigen::Matrix3d axes = solver.eigenvectors();
  if (axes.determinant() < 0) axes.col(2) = -axes.col(2);
  // Uniform box: I1 = mass (b^2 + c^2) / 12 and so on; a^2 = 6 (I2 + I3 - I1) / mass.
  for (int k = 0; k < 3; ++k) {
    const double sq = 6.0 * (m.sum() - 2.0 * m(k)) / mass;
    box.size[static_cast<std::size_t>(k)] = std::sqrt(std::max(sq, 1e-6));
  }
  const Eigen::Quaterniond q(axes);
  box.frame = {q.w(), q.x(), q.y(), q.z()};
  return box;
}

std::string scene_json(const SceneDescription& scene, std::uint64_t generation) {
  std::string out = "{\"type\":\"scene\",\"generation\":";
  integer(out, static_cast<std::int64_t>(generation));
  out += ",\"name\":";
  string(out, scene.scene_name);
  out += ",\"dt\":";
  number(out, scene.dt);
  out += ",\"publish_every\":";
  integer(out, scene.publish_every);
  out += ",\"gravity\":";
  numbers(out, scene.gravity.data(), 3);
  out += ",\"max_force\":";
  number(out, scene.max_force);
  out += ",\"max_torque\":";
  number(out, scene.max_torque);
  out += ",\"bodies\":[";
  if (scene.lengths_agree()) {
    for (std::size_t i = 0; i < scene.body_count(); ++i) {
      if (i) out += ',';
      out += "{\"id\":";
      integer(out, scene.ids[i]);
      out += ",\"name\":";
      string(out, scene.names[i]);
      out += ",\"mass\":";
      number(out, scene.masses[i]);
      out += ",\"inertia\":";
      numbers(out, &scene.inertia[6 * i], 6);
      const std::string_view shape = client::shape_name(scene.shape_kinds[i]);
      if (!shape.empty()) {
        out += ",\"shape\":";
        string(out, shape);
        out += ",\"dims\":";
        numbers(out, &scene.shape_dims[3 * i], 3);
      } else {
        const MomentBox box = box_of_moments(scene.masses[i], &scene.inertia[6 * i]);
        out += ",\"shape\":\"box\",\"from_moments\":true,\"dims\":";
        numbers(out, box.size.data(), 3);
        out += ",\"frame\":";
        numbers(out, box.frame.data(), 4);
      }
      out += '}';
    }
  }
  out += ']';
  // The static parts (planes, then static shapes), only for a scene that has them: a plane as its
  // frame (z = 0 of it, solid below), a shape as its pose and dims as a body's.
  if (scene.lengths_agree() && scene.part_count() > 0) {
    out += ",\"parts\":[";
    for (std::size_t i = 0; i < scene.part_count(); ++i) {
      if (i) out += ',';
      out += "{\"name\":";
      string(out, scene.part_names[i]);
      out += ",\"shape\":";
      string(out, client::shape_name(scene.part_kinds[i]));
      out += ",\"p\":";
      numbers(out, &scene.part_position[3 * i], 3);
      out += ",\"q\":";
      numbers(out, &scene.part_orientation[4 * i], 4);
      out += ",\"dims\":";
      numbers(out, &scene.part_dims[3 * i], 3);
      out += '}';
    }
    out += ']';
  }
  out += '}';
  return out;
}

std::string stats_json(const StatsReport& s) {
  const RejectCounts& r = s.rejected;
  const std::int64_t refused = r.non_finite + r.unknown_body + r.over_limit + r.undecodable +
                               r.stale_sequence + r.queue_full + r.invalid + r.over_share +
                               r.rate_limited + r.not_permitted;
  std::string out = "{\"type\":\"stats\",\"tick\":";
  integer(out, s.tick);
  out += ",\"sim_time\":";
  number(out, s.sim_time);
  out += ",\"paused\":";
  out += s.paused ? "true" : "false";
  out += ",\"rtf\":";
  number(out, s.rtf_last_second);
  out += ",\"lateness_p99_us\":";
  number(out, s.lateness_p99_us);
  out += ",\"overruns\":";
  integer(out, s.overruns);
  out += ",\"refused\":";
  integer(out, refused);
  out += ",\"accepted\":";
  integer(out, s.commands_accepted);
  out += ",\"frozen\":";
  integer(out, s.bodies_frozen);
  out += '}';
  return out;
}

std::string wrenches_json(const std::vector<AcceptedCommand>& accepted,
                          const std::vector<std::int64_t>& until) {
  std::string out = "{\"type\":\"wrenches\",\"wrenches\":[";
  std::size_t skip = 0, wrenches = 0;
  for (const AcceptedCommand& a : accepted)
    wrenches += a.kind == AcceptedKind::kWrench ? 1 : 0;
  if (wrenches > kMaxWrenchesShown) skip = wrenches - kMaxWrenchesShown;
  const auto frame = [](Frame f) { return '"' + std::string(rigid::frame_name(f)) + '"'; };
  const bool with_until = until.size() == accepted.size();
  bool first = true;
  for (std::size_t i = 0; i < accepted.size(); ++i) {
    const AcceptedCommand& a = accepted[i];
    if (a.kind != AcceptedKind::kWrench) continue;
    if (skip > 0) {
      --skip;
      continue;
    }
    if (!first) out += ',';
    first = false;
    out += "{\"body\":";
    integer(out, a.body_id);
    out += ",\"tick\":";
    integer(out, a.tick);
    out += ",\"ttl\":";
    number(out, a.ttl);
    out += ",\"force\":";
    numbers(out, a.force.data(), 3);
    out += ",\"force_frame\":";
    out += frame(a.force_frame);
    out += ",\"point\":";
    numbers(out, a.point.data(), 3);
    out += ",\"torque\":";
    numbers(out, a.torque.data(), 3);
    out += ",\"torque_frame\":";
    out += frame(a.torque_frame);
    out += ",\"key\":";
    integer(out, a.key);
    if (with_until) {
      out += ",\"until\":";
      integer(out, until[i]);
    }
    out += '}';
  }
  out += "]}";
  return out;
}

std::string hello_json(bool read_only, std::uint64_t connection, bool playback) {
  std::string out = "{\"type\":\"hello\",\"read_only\":";
  out += read_only ? "true" : "false";
  out += ",\"connection\":";
  integer(out, static_cast<std::int64_t>(connection));
  out += playback ? ",\"mode\":\"playback\"}" : ",\"mode\":\"live\"}";
  return out;
}

std::string reply_json(std::int64_t id, std::string_view op, bool ok, std::string_view outcome,
                       std::int64_t tick, std::string_view message) {
  std::string out = "{\"type\":\"reply\",\"id\":";
  integer(out, id);
  out += ",\"op\":";
  string(out, op);
  out += ",\"ok\":";
  out += ok ? "true" : "false";
  out += ",\"outcome\":";
  string(out, outcome);
  out += ",\"tick\":";
  integer(out, tick);
  out += ",\"message\":";
  string(out, message);
  out += '}';
  return out;
}

// Playback (rigid-view FILE).
std::string playback_json(const PlaybackStatus& s) {
  std::string out = "{\"type\":\"playback\",\"file\":";
  string(out, s.file);
  out += ",\"playing\":";
  out += s.playing ? "true" : "false";
  out += ",\"speed\":";
  number(out, s.speed);
  out += ",\"start\":";
  number(out, s.start);
  out += ",\"end\":";
  number(out, s.end);
  out += ",\"position\":";
  number(out, s.position);
  out += ",\"tick\":";
  integer(out, s.tick);
  out += ",\"sim_time\":";
  number(out, s.sim_time);
  out += ",\"index\":";
  integer(out, static_cast<std::int64_t>(s.index));
  out += ",\"states\":";
  integer(out, static_cast<std::int64_t>(s.states));
  out += '}';
  return out;
}
// End of playback.

std::string error_json(std::string_view message) {
  std::string out = "{\"type\":\"error\",\"message\":";
  string(out, message);
  out += '}';
  return out;
}

std::string_view op_name(Op op) {
  switch (op) {
    case Op::kPause:
      return "pause";
    case Op::kResume:
      return "resume";
    case Op::kStep:
      return "step";
    case Op::kReset:
      return "reset";
    case Op::kPush:
      return "push";
    case Op::kPlay:
      return "play";
    case Op::kSeek:
      return "seek";
    case Op::kSpeed:
      return "speed";
    case Op::kWatch:
      return "watch";
    case Op::kSetState:
      return "set_state";
    case Op::kResetBody:
      return "reset_body";
  }
  return "?";
}

std::variant<PageCommand, std::string> parse_command(std::string_view text) {
  if (text.size() > kMaxCommandBytes) return std::string("command longer than 512 bytes");
  PageCommand c;
  std::string_view op;
  bool have_id = false, have_steps = false, have_body = false, have_force = false,
       have_point = false, have_speed = false;
  Reader reader(text);
  const std::string error = reader.object([&](std::string_view key, const Reader::Value& v) {
    using K = Reader::Value::Kind;
    if (key == "op") {
      if (v.kind != K::kString) return std::string("op: expected a string");
      op = v.text;
    } else if (key == "id") {
      if (v.kind != K::kNumber || !whole(v.num, 0, static_cast<double>(kMaxCommandId)))
        return std::string("id: expected an integer in [0, 2^53]");
      c.id = static_cast<std::int64_t>(v.num);
      have_id = true;
    } else if (key == "steps") {
      if (v.kind != K::kNumber || !whole(v.num, 1, static_cast<double>(kMaxSteps)))
        return std::string("steps: expected an integer in [1, 1000000]");
      c.steps = static_cast<std::int64_t>(v.num);
      have_steps = true;
    } else if (key == "body") {
      if (v.kind != K::kNumber || !whole(v.num, 0, 2147483647.0))
        return std::string("body: expected a body id >= 0");
      c.body = static_cast<std::int32_t>(v.num);
      have_body = true;
    } else if (key == "force" || key == "point") {
      const double limit = key == "force" ? kMaxPushForce : kMaxPushPoint;
      if (v.kind != K::kArray || v.array.size() != 3)
        return std::string(key) + ": expected [x, y, z]";
      rigid::Vec3& out = key == "force" ? c.force : c.point;
      for (std::size_t k = 0; k < 3; ++k) {
        if (std::abs(v.array[k]) > limit)
          return std::string(key) + ": component beyond " + (key == "force" ? "1e4" : "100");
        out[k] = v.array[k];
      }
      (key == "force" ? have_force : have_point) = true;
    } else if (key == "position" || key == "velocity" || key == "angular_velocity" ||
               key == "orientation") {
      const bool q = key == "orientation";
      const std::size_t n = q ? 4 : 3;
      const double limit = q ? 1.01 : kMaxEditValue;  // rigidd wants a unit quaternion
      if (v.kind != K::kArray || v.array.size() != n)
        return std::string(key) + (q ? ": expected [w, x, y, z]" : ": expected [x, y, z]");
      for (std::size_t k = 0; k < n; ++k) {
        if (!(std::abs(v.array[k]) <= limit))
          return std::string(key) + ": component beyond " + (q ? "1.01" : "1e9");
      }
      rigid::StateEdit& s = c.state;
      if (key == "position") {
        std::copy_n(v.array.begin(), 3, s.position.begin());
        s.set |= rigid::kSetPosition;
      } else if (key == "velocity") {
        std::copy_n(v.array.begin(), 3, s.linear_velocity.begin());
        s.set |= rigid::kSetLinearVelocity;
      } else if (key == "angular_velocity") {
        std::copy_n(v.array.begin(), 3, s.angular_velocity.begin());
        s.set |= rigid::kSetAngularVelocity;
      } else {
        std::copy_n(v.array.begin(), 4, s.orientation.begin());
        s.set |= rigid::kSetOrientation;
      }
      // Playback (rigid-view FILE).
    } else if (key == "tick") {
      if (v.kind != K::kNumber || !whole(v.num, 0, static_cast<double>(kMaxCommandId)))
        return std::string("tick: expected an integer in [0, 2^53]");
      c.tick = static_cast<std::int64_t>(v.num);
    } else if (key == "time") {
      if (v.kind != K::kNumber || std::abs(v.num) > kMaxSeekTime)
        return std::string("time: expected a number of seconds in [-1e12, 1e12]");
      c.time = v.num;
    } else if (key == "speed") {
      if (v.kind != K::kNumber || !(v.num >= kMinPlaybackSpeed && v.num <= kMaxPlaybackSpeed))
        return std::string("speed: expected a number in [1/64, 64]");
      c.speed = v.num;
      have_speed = true;
      // End of playback.
    } else {
      return "unknown field " + std::string(key);
    }
    return std::string();
  });
  if (!error.empty()) return error;
  if (op == "pause") {
    c.op = Op::kPause;
  } else if (op == "resume") {
    c.op = Op::kResume;
  } else if (op == "reset") {
    c.op = Op::kReset;
  } else if (op == "step") {
    c.op = Op::kStep;
    if (!have_steps) return std::string("step: missing steps");
  } else if (op == "push") {
    c.op = Op::kPush;
    if (!have_body || !have_force || !have_point)
      return std::string("push: needs body, force and point");
    if (have_speed || c.tick >= 0 || c.time || c.state.set != 0)
      return std::string("push: unexpected field");
    return c;
  } else if (op == "set_state" || op == "reset_body") {
    c.op = op == "set_state" ? Op::kSetState : Op::kResetBody;
    if (!have_id) return std::string(op) + ": missing id";
    if (!have_body) return std::string(op) + ": missing body";
    if (c.op == Op::kSetState && c.state.set == 0)
      return std::string(
          "set_state: needs one of position, orientation, velocity, "
          "angular_velocity");
    if (c.op == Op::kResetBody && c.state.set != 0)
      return std::string("reset_body: unexpected field");
    if (have_force || have_point || have_steps || have_speed || c.tick >= 0 || c.time)
      return std::string(op) + ": unexpected field";
    return c;
  } else if (op == "watch") {
    c.op = Op::kWatch;  // no answer: no id needed; without a body, none
    if (have_force || have_point || have_steps || have_speed || c.tick >= 0 || c.time ||
        c.state.set != 0)
      return std::string("watch: unexpected field");
    return c;
    // Playback (rigid-view FILE).
  } else if (op == "play") {
    c.op = Op::kPlay;
  } else if (op == "seek") {
    c.op = Op::kSeek;
    if ((c.tick >= 0) == c.time.has_value()) return std::string("seek: needs one of tick and time");
  } else if (op == "speed") {
    c.op = Op::kSpeed;
    if (!have_speed) return std::string("speed: missing speed");
    // End of playback.
  } else {
    return op.empty() ? std::string("missing op") : "unknown op " + std::string(op);
  }
  if (!have_id) return std::string(op) + ": missing id";
  if (have_body || have_force || have_point || c.state.set != 0 ||
      (have_steps && c.op != Op::kStep) || (have_speed && c.op != Op::kSpeed) ||
      ((c.tick >= 0 || c.time) && c.op != Op::kSeek))
    return std::string(op) + ": unexpected field";
  return c;
}

// Playback (rigid-view FILE).
std::string refusal_in_mode(const PageCommand& c, bool playback) {
  const bool for_playback = c.op == Op::kPlay || c.op == Op::kSeek || c.op == Op::kSpeed;
  const bool for_rigidd = c.op == Op::kResume || c.op == Op::kStep || c.op == Op::kReset ||
                          c.op == Op::kPush || c.op == Op::kSetState || c.op == Op::kResetBody;
  if (playback && for_rigidd) {
    return std::string(op_name(c.op)) +
           ": not while playing a recording (there is no rigidd to command; use play, pause, "
           "seek and speed)";
  }
  if (!playback && for_playback)
    return std::string(op_name(c.op)) + ": only when playing a recording (rigid-view FILE)";
  return {};
}
// End of playback.

}  // namespace rigid::view
