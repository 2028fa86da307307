#include "record/export_mcap.hpp"

#include <google/protobuf/descriptor.pb.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <map>
#include <ostream>
#include <set>

#include "cli/state_rows.hpp"
#include "common/lcm_log.hpp"
#include "common/log_records.hpp"
#include "common/record_file.hpp"
#include "foxglove/FrameTransforms.pb.h"
#include "foxglove/SceneUpdate.pb.h"
#include "record/export_csv.hpp"
#include "record/mcap_writer.hpp"
#include "rigid/client/names.hpp"
#include "transport/lcm/lcm_codec.hpp"
#include "transport/topic.hpp"
#include "util/atomic_file.hpp"

namespace rigid::record {
namespace {

constexpr std::uint64_t kSceneEvery = 1'000'000'000;  // ns of log time between SceneUpdates

// The schema data MCAP's protobuf profile asks for: a FileDescriptorSet holding the message's file
// and every file it imports, dependencies first ("as produced by protoc --include_imports").
std::string descriptor_set(const google::protobuf::Descriptor* message) {
  google::protobuf::FileDescriptorSet set;
  std::set<std::string> added;
  const std::function<void(const google::protobuf::FileDescriptor*)> add =
      [&](const google::protobuf::FileDescriptor* file) {
        if (!added.insert(std::string(file->name())).second) return;
        for (int i = 0; i < file->dependency_count(); ++i)
          add(file->dependency(i));
        file->CopyTo(set.add_file());
      };
  add(message->file());
  return set.SerializeAsString();
}

// Protobuf wire format, for the one message written by hand (FrameTransforms: a thousand bodies
// a state, where building the generated messages would cost more than the rest of the export).
// The field numbers are those of msgs/foxglove/FrameTransform.proto; the test decodes the result
// with the embedded schema.
char* put_varint(char* p, std::uint64_t v) {
  while (v >= 0x80) {
    *p++ = static_cast<char>(v | 0x80);
    v >>= 7;
  }
  *p++ = static_cast<char>(v);
  return p;
}
std::size_t varint_size(std::uint64_t v) {
  std::size_t n = 1;
  for (; v >= 0x80; v >>= 7)
    ++n;
  return n;
}
// A double field (wire type 1, 64-bit), written even when zero so that every bit is kept.
char* put_double(char* p, int field, double v) {
  *p++ = static_cast<char>(field << 3 | 1);
  std::memcpy(p, &v, 8);
  return p + 8;
}
char* put_bytes(char* p, int field, std::string_view v) {
  *p++ = static_cast<char>(field << 3 | 2);
  p = put_varint(p, v.size());
  std::memcpy(p, v.data(), v.size());
  return p + v.size();
}

// google.protobuf.Timestamp of a time in ns since the epoch.
std::string timestamp_bytes(std::uint64_t ns) {
  char buf[32];
  char* p = buf;
  *p++ = static_cast<char>(1 << 3 | 0);
  p = put_varint(p, ns / 1'000'000'000);
  *p++ = static_cast<char>(2 << 3 | 0);
  p = put_varint(p, ns % 1'000'000'000);
  return std::string(buf, p);
}

void set_timestamp(google::protobuf::Timestamp* t, std::uint64_t ns) {
  t->set_seconds(static_cast<std::int64_t>(ns / 1'000'000'000));
  t->set_nanos(static_cast<std::int32_t>(ns % 1'000'000'000));
}

std::uint64_t as_time(std::int64_t ns) {
  return ns > 0 ? static_cast<std::uint64_t>(ns) : 0;
}

// A colour per body, spread around the hue circle (golden-ratio steps) so neighbours differ.
void set_color(foxglove::Color* c, std::size_t i) {
  const double h = std::fmod(0.13 + 0.6180339887498949 * static_cast<double>(i), 1.0) * 6.0;
  const double x = 1.0 - std::abs(std::fmod(h, 2.0) - 1.0);
  double rgb[3] = {0, 0, 0};
  const int sector = static_cast<int>(h);
  const int hi[6] = {0, 1, 1, 2, 2, 0};
  const int lo[6] = {1, 0, 2, 1, 0, 2};
  rgb[hi[sector % 6]] = 1.0;
  rgb[lo[sector % 6]] = x;
  c->set_r(0.25 + 0.7 * rgb[0]);
  c->set_g(0.25 + 0.7 * rgb[1]);
  c->set_b(0.25 + 0.7 * rgb[2]);
  c->set_a(0.9);
}

void set_pose(foxglove::Pose* pose, const Eigen::Vector3d& p, const Eigen::Quaterniond& q) {
  pose->mutable_position()->set_x(p.x());
  pose->mutable_position()->set_y(p.y());
  pose->mutable_position()->set_z(p.z());
  pose->mutable_orientation()->set_x(q.x());
  pose->mutable_orientation()->set_y(q.y());
  pose->mutable_orientation()->set_z(q.z());
  pose->mutable_orientation()->set_w(q.w());
}

void set_size(foxglove::Vector3* v, double x, double y, double z) {
  v->set_x(x);
  v->set_y(y);
  v->set_z(z);
}

// The primitives drawing body i of `scene`, in the body's frame (B, origin at the centre of mass).
void add_shape(const rigid::SceneDescription& scene, std::size_t i, foxglove::SceneEntity& e) {
  const double* d = &scene.shape_dims[3 * i];
  const Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  const Eigen::Quaterniond identity = Eigen::Quaterniond::Identity();
  const auto sphere = [&](const Eigen::Vector3d& at, double dx, double dy, double dz) {
    foxglove::SpherePrimitive* s = e.add_spheres();
    set_pose(s->mutable_pose(), at, identity);
    set_size(s->mutable_size(), dx, dy, dz);
    set_color(s->mutable_color(), i);
  };
  switch (scene.shape_kinds[i]) {
    case rigid::ShapeKind::kBox: {
      foxglove::CubePrimitive* c = e.add_cubes();
      set_pose(c->mutable_pose(), origin, identity);
      set_size(c->mutable_size(), d[0], d[1], d[2]);
      set_color(c->mutable_color(), i);
      return;
    }
    case rigid::ShapeKind::kSphere:
      sphere(origin, 2 * d[0], 2 * d[0], 2 * d[0]);
      return;
    case rigid::ShapeKind::kEllipsoid:  // Foxglove's sphere takes a diameter per axis
      sphere(origin, 2 * d[0], 2 * d[1], 2 * d[2]);
      return;
    case rigid::ShapeKind::kCylinder:
    case rigid::ShapeKind::kCapsule: {
      foxglove::CylinderPrimitive* c = e.add_cylinders();
      set_pose(c->mutable_pose(), origin, identity);
      set_size(c->mutable_size(), 2 * d[0], 2 * d[0], d[1]);
      c->set_bottom_scale(1.0);
      c->set_top_scale(1.0);
      set_color(c->mutable_color(), i);
      if (scene.shape_kinds[i] == rigid::ShapeKind::kCapsule) {  // and its two hemispherical caps
        sphere(Eigen::Vector3d(0, 0, d[1] / 2), 2 * d[0], 2 * d[0], 2 * d[0]);
        sphere(Eigen::Vector3d(0, 0, -d[1] / 2), 2 * d[0], 2 * d[0], 2 * d[0]);
      }
      return;
    }
    case rigid::ShapeKind::kNone:
      break;
  }
  // No shape: the uniform box with the body's principal moments, along its principal axes. A box
  // of mass m and edges a, b, c has moments m (b^2 + c^2) / 12, ..., so a^2 = 6 (I2 + I3 - I1) / m.
  const double* t = &scene.inertia[6 * i];  // Ixx, Iyy, Izz, Ixy, Ixz, Iyz
  Eigen::Matrix3d inertia;
  inertia << t[0], t[3], t[4], t[3], t[1], t[5], t[4], t[5], t[2];
  const double m = scene.masses[i];
  if (!(m > 0) || !(inertia.cwiseAbs().maxCoeff() > 0)) {
    // A point mass (no inertia): a small marker sphere.
    sphere(origin, 0.05, 0.05, 0.05);
    return;
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(inertia);
  const Eigen::Vector3d I = eig.eigenvalues();
  Eigen::Matrix3d axes = eig.eigenvectors();
  if (axes.determinant() < 0) axes.col(2) = -axes.col(2);  // a rotation, not a reflection
  const auto edge = [&](int k) {
    const double s = 6.0 * (I.sum() - 2.0 * I[k]) / m;
    return std::sqrt(std::max(s, 1e-6));
  };
  foxglove::CubePrimitive* c = e.add_cubes();
  set_pose(c->mutable_pose(), origin, Eigen::Quaterniond(axes).normalized());
  set_size(c->mutable_size(), edge(0), edge(1), edge(2));
  set_color(c->mutable_color(), i);
}

struct Summary {
  std::int64_t states = 0;
  std::string note;
};

// Turns the records of a recording into MCAP messages on the channels above.
class FoxgloveOut {
 public:
  explicit FoxgloveOut(const std::string& path)
      : file_(path),
        writer_([this](std::string_view bytes) { write_out(bytes); }, "",
                common::software_version() + " rigid-record export --mcap") {
    const auto schema = [&](const google::protobuf::Descriptor* d) {
      return writer_.add_schema(d->full_name(), "protobuf", descriptor_set(d));
    };
    transforms_ = writer_.add_channel(schema(foxglove::FrameTransforms::descriptor()),
                                      "/rigid/transforms", "protobuf");
    bodies_ = writer_.add_channel(schema(foxglove::SceneUpdate::descriptor()), "/rigid/bodies",
                                  "protobuf");
    state_ =
        writer_.add_channel(schema(msgs::StateRecord::descriptor()), "/rigid/state", "protobuf");
    scene_ =
        writer_.add_channel(schema(msgs::SceneRecord::descriptor()), "/rigid/scene", "protobuf");
    stats_ =
        writer_.add_channel(schema(msgs::StatsRecord::descriptor()), "/rigid/stats", "protobuf");
    accepted_ = writer_.add_channel(schema(msgs::CommandRecord::descriptor()), "/rigid/accepted",
                                    "protobuf");
  }

  void scene(const msgs::SceneRecord& r, std::uint64_t log_time) {
    if (common::from_record(r, scene_desc_)) {
      names_ = clients::BodyNames(scene_desc_);
      state_ids_.clear();  // names by position are looked up again
      scene_dirty_ = true;
    }
    writer_.write(scene_, seq_[scene_]++, log_time, log_time, r.SerializeAsString());
  }

  void state(const msgs::StateRecord& r, std::uint64_t log_time, const std::string& where) {
    const std::size_t n = static_cast<std::size_t>(r.ids_size());
    if (static_cast<std::size_t>(r.position_size()) != 3 * n ||
        static_cast<std::size_t>(r.orientation_size()) != 4 * n ||
        static_cast<std::size_t>(r.linear_velocity_size()) != 3 * n ||
        static_cast<std::size_t>(r.angular_velocity_size()) != 3 * n) {
      throw common::LogFileError(where + ": a state whose arrays disagree with its body count");
    }
    const std::uint64_t publish = r.stamp_ns() > 0 ? as_time(r.stamp_ns()) : log_time;
    if (scene_dirty_ || log_time >= last_scene_update_ + kSceneEvery) scene_update(log_time);
    writer_.write_with(state_, seq_[state_]++, log_time, publish,
                       [&r](std::string& s) { r.AppendToString(&s); });
    transforms(r, log_time, publish);
    ++summary_.states;
  }

  void stats(const msgs::StatsRecord& r, std::uint64_t log_time) {
    writer_.write(stats_, seq_[stats_]++, log_time, log_time, r.SerializeAsString());
  }

  void command(const msgs::CommandRecord& r, std::uint64_t log_time) {
    const std::uint64_t publish = r.stamp_ns() > 0 ? as_time(r.stamp_ns()) : log_time;
    writer_.write(accepted_, seq_[accepted_]++, log_time, publish, r.SerializeAsString());
  }

  Summary commit() {
    writer_.finish();
    flush();
    file_.commit();
    return summary_;
  }
  Summary& summary() { return summary_; }
  std::uint64_t bytes() const { return writer_.bytes(); }

 private:
  // One SceneEntity per body of the scene, in the body's frame (frame_locked: it moves with it).
  void scene_update(std::uint64_t log_time) {
    scene_dirty_ = false;
    last_scene_update_ = log_time;
    foxglove::SceneUpdate update;
    const std::size_t n = scene_desc_.lengths_agree() ? scene_desc_.body_count() : 0;
    for (std::size_t i = 0; i < n; ++i) {
      foxglove::SceneEntity* e = update.add_entities();
      set_timestamp(e->mutable_timestamp(), log_time);
      e->set_frame_id(scene_desc_.names[i]);
      e->set_id(scene_desc_.names[i]);
      e->set_frame_locked(true);
      const auto meta = [e](std::string key, std::string value) {
        foxglove::KeyValuePair* kv = e->add_metadata();
        kv->set_key(std::move(key));
        kv->set_value(std::move(value));
      };
      meta("id", std::to_string(scene_desc_.ids[i]));
      meta("mass", std::to_string(scene_desc_.masses[i]));
      const std::string_view shape = client::shape_name(scene_desc_.shape_kinds[i]);
      meta("shape",
           shape.empty() ? "none (drawn as the box of its principal moments)" : std::string(shape));
      add_shape(scene_desc_, i, *e);
    }
    writer_.write(bodies_, seq_[bodies_]++, log_time, log_time, update.SerializeAsString());
  }

  // FrameTransforms: per body, "world" -> its name, translation = position, rotation = its
  // orientation reordered to Foxglove's x, y, z, w. Encoded by hand (see put_double).
  void transforms(const msgs::StateRecord& r, std::uint64_t log_time, std::uint64_t) {
    const std::size_t n = static_cast<std::size_t>(r.ids_size());
    if (state_ids_.size() != n ||
        !std::equal(state_ids_.begin(), state_ids_.end(), r.ids().begin())) {
      state_ids_.assign(r.ids().begin(), r.ids().end());
      frame_names_.clear();
      for (const std::int32_t id : state_ids_)
        frame_names_.push_back(names_.name(id));
    }
    const std::string stamp = timestamp_bytes(log_time);
    constexpr std::string_view kWorld = "world";
    constexpr std::size_t kTranslation = 3 * 9;  // three tagged doubles
    constexpr std::size_t kRotation = 4 * 9;
    writer_.write_with(transforms_, seq_[transforms_]++, log_time, log_time, [&](std::string& s) {
      std::size_t bound = 0;
      for (const std::string& name : frame_names_)
        bound += 2 * 10 + stamp.size() + kWorld.size() + name.size() + 3 * 2 + 2 * 10 +
                 kTranslation + kRotation + 8;
      const std::size_t start = s.size();
      s.resize(start + bound);
      char* p = s.data() + start;
      const double* pos = r.position().data();
      const double* q = r.orientation().data();  // w, x, y, z per body
      for (std::size_t i = 0; i < n; ++i) {
        const std::string& name = frame_names_[i];
        const std::size_t inner = 1 + varint_size(stamp.size()) + stamp.size() + 2 + kWorld.size() +
                                  1 + varint_size(name.size()) + name.size() + 2 + kTranslation +
                                  2 + kRotation;
        *p++ = static_cast<char>(1 << 3 | 2);  // FrameTransforms.transforms
        p = put_varint(p, inner);
        p = put_bytes(p, 1, stamp);            // timestamp
        p = put_bytes(p, 2, kWorld);           // parent_frame_id
        p = put_bytes(p, 3, name);             // child_frame_id
        *p++ = static_cast<char>(4 << 3 | 2);  // translation
        *p++ = static_cast<char>(kTranslation);
        p = put_double(p, 1, pos[3 * i]);
        p = put_double(p, 2, pos[3 * i + 1]);
        p = put_double(p, 3, pos[3 * i + 2]);
        *p++ = static_cast<char>(5 << 3 | 2);  // rotation
        *p++ = static_cast<char>(kRotation);
        p = put_double(p, 1, q[4 * i + 1]);
        p = put_double(p, 2, q[4 * i + 2]);
        p = put_double(p, 3, q[4 * i + 3]);
        p = put_double(p, 4, q[4 * i]);
      }
      s.resize(static_cast<std::size_t>(p - s.data()));
    });
  }

  // The writer's output is gathered into large writes.
  void write_out(std::string_view bytes) {
    if (bytes.size() >= kBuffer) {
      flush();
      file_.write(bytes);
      return;
    }
    buffer_.append(bytes);
    if (buffer_.size() >= kBuffer) flush();
  }
  void flush() {
    file_.write(buffer_);
    buffer_.clear();
  }
  static constexpr std::size_t kBuffer = 1 << 20;

  util::AtomicFile file_;
  std::string buffer_;
  McapWriter writer_;
  std::uint16_t transforms_ = 0, bodies_ = 0, state_ = 0, scene_ = 0, stats_ = 0, accepted_ = 0;
  std::map<std::uint16_t, std::uint32_t> seq_;
  rigid::SceneDescription scene_desc_;
  clients::BodyNames names_;
  bool scene_dirty_ = true;
  std::uint64_t last_scene_update_ = 0;
  std::vector<std::int32_t> state_ids_;
  std::vector<std::string> frame_names_;
  Summary summary_;
};

std::string damage_note(const common::Damage& d) {
  return "stopped at a damaged tail at offset " + std::to_string(d.offset) + " (" + d.reason +
         "), " + std::to_string(d.bytes) + " bytes not read";
}

Summary from_rigid_log(const RecordOptions& o) {
  common::RecordReader reader(o.file);
  msgs::LogRecord r;
  std::unique_ptr<FoxgloveOut> out;
  std::uint64_t start = 0;
  const auto at = [&](std::int64_t recorded_ns) { return start + as_time(recorded_ns); };
  const auto where = [&] { return o.file + ": record " + std::to_string(reader.records()); };
  while (reader.next(r)) {
    if (r.has_header()) {
      if (r.header().kind() == msgs::LogHeader::JOURNAL) {
        throw common::LogFileError(
            o.file +
            " is a journal (rigidd --journal): it holds accepted commands and state hashes, no "
            "states; replay it with rigid-sim --replay --csv, or record states with rigid-record "
            "record");
      }
      start = as_time(r.header().start_unix_ns());
      if (!out) out = std::make_unique<FoxgloveOut>(o.mcap);
      if (r.header().scene().ids_size() > 0) out->scene(r.header().scene(), start);
      continue;
    }
    if (!out) out = std::make_unique<FoxgloveOut>(o.mcap);
    if (r.has_scene()) {
      out->scene(r.scene(), at(r.scene().recorded_ns()));
    } else if (r.has_state()) {
      out->state(r.state(), at(r.state().recorded_ns()), where());
    } else if (r.has_stats()) {
      out->stats(r.stats(), at(r.stats().recorded_ns()));
    } else if (r.has_command()) {
      out->command(r.command(), at(r.command().recorded_ns()));
    }
  }
  if (!out || out->summary().states == 0) {
    throw common::LogFileError(o.file + ": no states to export" +
                               (reader.damage() ? " (" + damage_note(*reader.damage()) + ")" : ""));
  }
  if (reader.damage()) out->summary().note = damage_note(*reader.damage());
  return out->commit();
}

Summary from_lcm_log(const RecordOptions& o, std::ostream& err) {
  std::map<std::string, std::int64_t> seen;
  {
    common::LcmLogReader reader(o.file);
    common::LcmEvent event;
    while (reader.next(event))
      ++seen[event.channel];
  }
  using transport::Topic;
  const transport::TopicNames names = transport::lcm_channel_names(lcm_log_prefix(o, seen));
  const std::string& state_channel = names[transport::index_of(Topic::kState)];
  const std::string& scene_channel = names[transport::index_of(Topic::kScene)];
  const std::string& stats_channel = names[transport::index_of(Topic::kStats)];
  const std::string& accepted_channel = names[transport::index_of(Topic::kAccepted)];
  if (!seen.contains(state_channel)) {
    throw common::LogFileError(o.file + ": no " + state_channel + " in this log");
  }
  transport::lcm::Codec codec;
  rigid::SceneDescription scene;
  bool have_scene = false;
  {  // The scene first (LCM sends it once a second, so it may come after the first states).
    common::LcmLogReader reader(o.file);
    common::LcmEvent event;
    while (!have_scene && reader.next(event)) {
      have_scene = event.channel == scene_channel &&
                   codec.decode(event.data, scene) == transport::DecodeStatus::kOk;
    }
  }
  if (!have_scene) {
    err << "rigid-record: export: no " << scene_channel << " in " << o.file
        << ": bodies are named by id and have no shapes\n";
  }
  FoxgloveOut out(o.mcap);
  common::LcmLogReader reader(o.file);
  common::LcmEvent event;
  std::int64_t first_us = -1;
  std::int64_t undecodable = 0;
  rigid::StateFrame frame;
  rigid::StatsReport stats;
  rigid::AcceptedCommand accepted;
  rigid::SceneDescription later_scene;
  msgs::StateRecord state_record;
  msgs::SceneRecord scene_record;
  msgs::StatsRecord stats_record;
  msgs::CommandRecord command_record;
  while (reader.next(event)) {
    if (first_us < 0) {
      first_us = event.timestamp_us;
      if (have_scene) {
        common::to_record(scene, 0, scene_record);
        out.scene(scene_record, as_time(event.timestamp_us) * 1000);
      }
    }
    const std::uint64_t t = as_time(event.timestamp_us) * 1000;
    const std::int64_t recorded_ns = (event.timestamp_us - first_us) * 1000;
    const auto ok = [&](transport::DecodeStatus s) {
      if (s != transport::DecodeStatus::kOk) ++undecodable;
      return s == transport::DecodeStatus::kOk;
    };
    if (event.channel == state_channel) {
      if (!ok(codec.decode(event.data, frame))) continue;
      common::to_record(frame, recorded_ns, state_record);
      out.state(state_record, t, o.file + ": event " + std::to_string(reader.events()));
    } else if (event.channel == stats_channel) {
      if (!ok(codec.decode(event.data, stats))) continue;
      common::to_record(stats, recorded_ns, stats_record);
      out.stats(stats_record, t);
    } else if (event.channel == accepted_channel) {
      if (!ok(codec.decode(event.data, accepted))) continue;
      common::to_record(accepted, recorded_ns, command_record);
      out.command(command_record, t);
    } else if (event.channel == scene_channel) {
      // rigidd repeats its scene once a second: only a change is a new scene.
      if (!ok(codec.decode(event.data, later_scene)) || later_scene == scene) continue;
      scene = later_scene;
      common::to_record(scene, recorded_ns, scene_record);
      out.scene(scene_record, t);
    }
  }
  if (out.summary().states == 0) throw common::LogFileError(o.file + ": no states to export");
  std::string note = reader.damage() ? damage_note(*reader.damage()) : "";
  if (undecodable > 0) {
    note += (note.empty() ? "" : "; ") + std::to_string(undecodable) +
            " events of rigidd's channels did not decode and were skipped";
  }
  out.summary().note = note;
  return out.commit();
}

}  // namespace

int export_mcap(const RecordOptions& o, std::ostream& out, std::ostream& err) {
  try {
    refuse_existing(o.mcap, o.force);
    const bool lcm = common::looks_like_lcm_log(o.file);
    const Summary s = lcm ? from_lcm_log(o, err) : from_rigid_log(o);
    out << o.mcap << ": " << s.states << " states from " << o.file
        << (lcm ? " (lcm-logger log)" : "") << '\n';
    if (!s.note.empty()) err << "rigid-record: export: " << s.note << '\n';
    return clients::kExitOk;
  } catch (const clients::UsageError& e) {
    err << "rigid-record: export: " << e.what() << '\n';
    return clients::kExitUsage;
  } catch (const std::runtime_error& e) {
    err << "rigid-record: " << e.what() << '\n';
    return clients::kExitFailed;
  }
}

}  // namespace rigid::record
