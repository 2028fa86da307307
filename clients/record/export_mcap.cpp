#include "record/export_mcap.hpp"

#include <algorithm>
#include <map>
#include <ostream>

#include "cli/state_rows.hpp"
#include "common/foxglove_messages.hpp"
#include "common/lcm_log.hpp"
#include "common/log_records.hpp"
#include "common/record_file.hpp"
#include "foxglove/FrameTransforms.pb.h"
#include "foxglove/SceneUpdate.pb.h"
#include "record/export_csv.hpp"
#include "record/mcap_writer.hpp"
#include "record/recorder.hpp"
#include "rigid/client/names.hpp"
#include "transport/lcm/lcm_codec.hpp"
#include "transport/topic.hpp"
#include "util/atomic_file.hpp"

namespace rigid::record {
namespace {

constexpr std::uint64_t kSceneEvery = 1'000'000'000;  // ns of log time between SceneUpdates

std::uint64_t as_time(std::int64_t ns) {
  return ns > 0 ? static_cast<std::uint64_t>(ns) : 0;
}

struct Summary {
  std::int64_t states = 0;
  std::int64_t contact_events = 0;
  std::string note;
};

// Turns the records of a recording into MCAP messages on the channels above.
class FoxgloveOut {
 public:
  // `zstd_level` 0: chunks uncompressed.
  FoxgloveOut(const std::string& path, int zstd_level)
      : file_(path),
        writer_([this](std::string_view bytes) { write_out(bytes); }, "",
                common::software_version() + " rigid-record export --mcap", 4u << 20, zstd_level) {
    const auto schema = [&](const google::protobuf::Descriptor* d) {
      return writer_.add_schema(d->full_name(), "protobuf", common::foxglove::descriptor_set(d));
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
    contacts_ = writer_.add_channel(schema(msgs::ContactRecord::descriptor()), "/rigid/contacts",
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

  // A tick's contact events, as recorded (publish time: rigidd's stamp).
  void contacts(const msgs::ContactRecord& r, std::uint64_t log_time) {
    const std::uint64_t publish = r.stamp_ns() > 0 ? as_time(r.stamp_ns()) : log_time;
    writer_.write(contacts_, seq_[contacts_]++, log_time, publish, r.SerializeAsString());
    summary_.contact_events += r.kinds_size();
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
    writer_.write(bodies_, seq_[bodies_]++, log_time, log_time,
                  common::foxglove::scene_update(scene_desc_, log_time, false));
  }

  // FrameTransforms: per body, "world" -> its name (foxglove_messages.hpp).
  void transforms(const msgs::StateRecord& r, std::uint64_t log_time, std::uint64_t) {
    const std::size_t n = static_cast<std::size_t>(r.ids_size());
    if (state_ids_.size() != n ||
        !std::equal(state_ids_.begin(), state_ids_.end(), r.ids().begin())) {
      state_ids_.assign(r.ids().begin(), r.ids().end());
      frame_names_.clear();
      for (const std::int32_t id : state_ids_)
        frame_names_.push_back(names_.name(id));
    }
    writer_.write_with(transforms_, seq_[transforms_]++, log_time, log_time, [&](std::string& s) {
      common::foxglove::append_frame_transforms(s, frame_names_, r.position().data(),
                                                r.orientation().data(), log_time);
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
  std::uint16_t transforms_ = 0, bodies_ = 0, state_ = 0, scene_ = 0, stats_ = 0, accepted_ = 0,
                contacts_ = 0;
  std::map<std::uint16_t, std::uint32_t> seq_;
  rigid::SceneDescription scene_desc_;
  clients::BodyNames names_;
  bool scene_dirty_ = true;
  std::uint64_t last_scene_update_ = 0;
  std::vector<std::int32_t> state_ids_;
  std::vector<std::string> frame_names_;
  Summary summary_;
};

// MCAP chunks in zstd at rigid-record's level, unless --compress none.
int zstd_level(const RecordOptions& o) {
  return o.compress ? kZstdLevel : 0;
}

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
        throw common::LogFileError(journal_has_no_states(o.file));
      }
      start = as_time(r.header().start_unix_ns());
      if (!out) out = std::make_unique<FoxgloveOut>(o.mcap, zstd_level(o));
      if (r.header().scene().ids_size() > 0) out->scene(r.header().scene(), start);
      continue;
    }
    if (!out) out = std::make_unique<FoxgloveOut>(o.mcap, zstd_level(o));
    if (r.has_scene()) {
      out->scene(r.scene(), at(r.scene().recorded_ns()));
    } else if (r.has_state()) {
      out->state(r.state(), at(r.state().recorded_ns()), where());
    } else if (r.has_stats()) {
      out->stats(r.stats(), at(r.stats().recorded_ns()));
    } else if (r.has_command()) {
      out->command(r.command(), at(r.command().recorded_ns()));
    } else if (r.has_contacts()) {
      out->contacts(r.contacts(), at(r.contacts().recorded_ns()));
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
  const std::string& contacts_channel = names[transport::index_of(Topic::kContacts)];
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
  FoxgloveOut out(o.mcap, zstd_level(o));
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
  rigid::ContactEvents contacts;
  msgs::ContactRecord contact_record;
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
    } else if (event.channel == contacts_channel) {
      if (!ok(codec.decode(event.data, contacts))) continue;
      common::to_record(contacts, recorded_ns, contact_record);
      out.contacts(contact_record, t);
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
        << (lcm ? " (lcm-logger log)" : "");
    if (s.contact_events > 0) out << ", " << s.contact_events << " contact events";
    out << '\n';
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
