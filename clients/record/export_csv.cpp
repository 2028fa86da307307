#include "record/export_csv.hpp"

#include <filesystem>
#include <map>
#include <ostream>

#include "cli/state_rows.hpp"
#include "common/lcm_log.hpp"
#include "common/log_records.hpp"
#include "common/record_file.hpp"
#include "transport/lcm/lcm_codec.hpp"
#include "transport/topic.hpp"
#include "util/atomic_file.hpp"
#include "util/state_csv.hpp"

namespace rigid::record {
namespace {

constexpr std::size_t kChunk = 1 << 20;  // CSV bytes buffered before a write

struct Exported {
  std::int64_t states = 0;
  std::int64_t rows = 0;
  std::string note;  // how the input ended, when not cleanly
};

// The CSV being written: rows buffered, then handed to the AtomicFile.
class CsvOut {
 public:
  explicit CsvOut(const std::string& path) : file_(path) { text_ += util::kStateCsvHeader; }
  void add(const rigid::StateFrame& f, const clients::BodyNames& names, Exported& e) {
    clients::append_frame_rows(f, names, text_);
    ++e.states;
    e.rows += static_cast<std::int64_t>(f.body_count());
    if (text_.size() >= kChunk) {
      file_.write(text_);
      text_.clear();
    }
  }
  void commit() {
    file_.write(text_);
    file_.commit();
  }

 private:
  util::AtomicFile file_;
  std::string text_;
};

std::string damage_note(const common::Damage& d) {
  return "stopped at a damaged tail at offset " + std::to_string(d.offset) + " (" + d.reason +
         "), " + std::to_string(d.bytes) + " bytes not read";
}

Exported from_rigid_log(const RecordOptions& o) {
  common::RecordReader reader(o.file);
  CsvOut csv(o.csv);
  Exported e;
  clients::BodyNames names;
  msgs::LogRecord r;
  rigid::StateFrame frame;
  rigid::SceneDescription scene;
  while (reader.next(r)) {
    if (r.has_header() && r.header().kind() == msgs::LogHeader::JOURNAL) {
      throw common::LogFileError(journal_has_no_states(o.file));
    }
    if (r.has_header() && common::from_record(r.header().scene(), scene)) {
      names = clients::BodyNames(scene);
    } else if (r.has_scene() && common::from_record(r.scene(), scene)) {
      names = clients::BodyNames(scene);
    } else if (r.has_state()) {
      if (!common::from_record(r.state(), frame)) {
        throw common::LogFileError(o.file + ": record " + std::to_string(reader.records()) +
                                   ": a state whose arrays disagree with its body count");
      }
      csv.add(frame, names, e);
    }
  }
  if (e.states == 0) {
    throw common::LogFileError(o.file + ": no states to export" +
                               (reader.damage() ? " (" + damage_note(*reader.damage()) + ")" : ""));
  }
  if (reader.damage()) e.note = damage_note(*reader.damage());
  csv.commit();
  return e;
}

// The channel names of rigidd's state and scene in an LCM log.
std::pair<std::string, std::string> lcm_channels(const RecordOptions& o,
                                                 const std::map<std::string, std::int64_t>& seen) {
  using transport::Topic;
  const transport::TopicNames n = transport::lcm_channel_names(lcm_log_prefix(o, seen));
  return {n[transport::index_of(Topic::kState)], n[transport::index_of(Topic::kScene)]};
}

Exported from_lcm_log(const RecordOptions& o, std::ostream& err) {
  // First pass: which channels, and the scene (LCM sends it once a second, so it may come after
  // the first states).
  std::map<std::string, std::int64_t> seen;
  {
    common::LcmLogReader reader(o.file);
    common::LcmEvent event;
    while (reader.next(event))
      ++seen[event.channel];
  }
  const auto [state_channel, scene_channel] = lcm_channels(o, seen);
  transport::lcm::Codec codec;
  rigid::SceneDescription scene;
  clients::BodyNames names;
  {
    common::LcmLogReader reader(o.file);
    common::LcmEvent event;
    while (reader.next(event)) {
      if (event.channel == scene_channel &&
          codec.decode(event.data, scene) == transport::DecodeStatus::kOk) {
        names = clients::BodyNames(scene);
        break;
      }
    }
  }
  if (names.empty()) {
    err << "rigid-record: export: no " << scene_channel << " in " << o.file
        << ": bodies are named by id\n";
  }
  common::LcmLogReader reader(o.file);
  CsvOut csv(o.csv);
  Exported e;
  common::LcmEvent event;
  rigid::StateFrame frame;
  std::int64_t undecodable = 0;
  while (reader.next(event)) {
    if (event.channel != state_channel) continue;
    if (codec.decode(event.data, frame) != transport::DecodeStatus::kOk) {
      ++undecodable;
      continue;
    }
    csv.add(frame, names, e);
  }
  if (reader.damage()) e.note = damage_note(*reader.damage());
  if (undecodable > 0) {
    e.note += (e.note.empty() ? "" : "; ") + std::to_string(undecodable) + " events on " +
              state_channel + " did not decode and were skipped";
  }
  if (e.states == 0) {
    throw common::LogFileError(o.file + ": no states on " + state_channel + " to export" +
                               (e.note.empty() ? "" : " (" + e.note + ")"));
  }
  csv.commit();
  return e;
}

}  // namespace

std::string lcm_log_prefix(const RecordOptions& o,
                           const std::map<std::string, std::int64_t>& seen) {
  try {
    return common::lcm_log_prefix(
        o.file, o.bus_prefix_given ? std::optional<std::string>(o.bus.prefix) : std::nullopt, seen);
  } catch (const common::SeveralPrefixes& e) {
    throw clients::UsageError(e.what());
  }
}

std::string journal_has_no_states(const std::string& path) {
  return path +
         " is a journal (rigidd --journal): it holds accepted commands and state hashes, no "
         "states; replay it with rigid-sim --replay --csv, or record states with rigid-record "
         "record";
}

void refuse_existing(const std::string& path, bool force) {
  if (!force && std::filesystem::exists(path)) {
    throw common::LogFileError(path + " already exists (--force overwrites it)");
  }
}

int export_csv(const RecordOptions& o, std::ostream& out, std::ostream& err) {
  try {
    refuse_existing(o.csv, o.force);
    const bool lcm = common::looks_like_lcm_log(o.file);
    const Exported e = lcm ? from_lcm_log(o, err) : from_rigid_log(o);
    out << o.csv << ": " << e.states << " states, " << e.rows << " rows from " << o.file
        << (lcm ? " (lcm-logger log)" : "") << '\n';
    if (!e.note.empty()) err << "rigid-record: export: " << e.note << '\n';
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
