// Re-running a journal, and the report at the end.
#include "common/replay.hpp"

#include <cinttypes>
#include <cstdio>
#include <fstream>
#include <memory>
#include <ostream>
#include <sstream>

#include "common/contact_csv.hpp"
#include "common/driven_world.hpp"
#include "common/journal_entry.hpp"
#include "common/log_records.hpp"
#include "common/record_file.hpp"
#include "common/state_conversion.hpp"
#include "common/state_hash.hpp"
#include "common/world_csv.hpp"
#include "rigid/names.hpp"
#include "scene/scene.hpp"
#include "util/atomic_file.hpp"

namespace rigid::common {
namespace {

// rigidd's default (loop::ServerOptions::wrench_capacity), for a journal that does not say.
constexpr std::uint64_t kDefaultWrenchCapacity = 4096;

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string hex(std::uint64_t v) {
  char buffer[24];
  std::snprintf(buffer, sizeof buffer, "%016" PRIx64, v);
  return buffer;
}

// The journal's header, checked: a JOURNAL of a schema this program reads.
msgs::LogHeader read_header(common::RecordReader& reader) {
  msgs::LogRecord record;
  if (!reader.next(record) || !record.has_header()) {
    throw std::runtime_error(reader.path() + ": no header record" +
                             (reader.damage() ? " (" + reader.damage()->reason + ")" : ""));
  }
  const msgs::LogHeader& h = record.header();
  if (h.kind() != msgs::LogHeader::JOURNAL) {
    throw std::runtime_error(reader.path() +
                             ": not a journal but a recording (rigid-record info describes it; "
                             "journals come from rigidd --journal)");
  }
  if (h.schema_version() > common::kLogSchemaVersion) {
    throw std::runtime_error(reader.path() + ": log schema version " +
                             std::to_string(h.schema_version()) + ", this program reads up to " +
                             std::to_string(common::kLogSchemaVersion));
  }
  return h;
}

scene::Scene journal_scene(const ReplayOptions& options, const msgs::LogHeader& h,
                           ReplayReport& report) {
  const std::string& journal = options.journal;
  if (options.scene.empty()) {
    if (h.scene_text().empty()) {
      throw SceneMismatch(journal + ": holds no copy of its scene: give the SCENE it ran");
    }
    report.scene = journal + " (its copy of " + h.scene().scene_name() + ")";
    return scene::parse_scene(h.scene_text(), journal + ":scene");
  }
  scene::Scene s = scene::load_scene(options.scene);
  report.scene = options.scene;
  if (h.scene_text().empty()) {
    report.warnings.push_back(journal + " holds no copy of its scene: cannot check that " +
                              options.scene + " is the scene it ran");
  } else if (read_text(options.scene) != h.scene_text()) {
    throw SceneMismatch(options.scene + ": not the scene " + journal + " was recorded with (" +
                        h.scene().scene_name() +
                        "); the journal holds a copy of it: leave SCENE out to use it");
  }
  return s;
}

}  // namespace

ReplayReport replay(const ReplayOptions& options, const StateSink& on_state,
                    const ContactSink& on_contacts) {
  ReplayReport r;
  r.journal = options.journal;
  common::RecordReader reader(r.journal);  // throws common::LogFileError, a std::runtime_error
  const msgs::LogHeader header = read_header(reader);
  const scene::Scene scene = journal_scene(options, header, r);
  for (const std::string& w : scene.warnings)
    r.warnings.push_back(w);

  r.software_version = header.software_version();
  if (header.software_version() != common::software_version()) {
    r.warnings.push_back("journal written by " + header.software_version() + ", replayed by " +
                         common::software_version() +
                         ": only the same build promises bit-identical states");
  }
  const double tick_dt = 1.0 / scene.rate_hz;
  const std::uint64_t capacity =
      header.wrench_capacity() > 0 ? header.wrench_capacity() : kDefaultWrenchCapacity;
  common::DrivenWorld driven(scene.world, tick_dt, scene.substeps, capacity);
  r.integrator = std::string(driven.world().integrator().name);
  r.rate_hz = scene.rate_hz;
  if (!header.integrator().empty() && header.integrator() != r.integrator) {
    r.warnings.push_back("the journal ran integrator " + header.integrator() + ", this replay " +
                         r.integrator);
  }

  std::unique_ptr<util::AtomicFile> csv;
  std::string rows;
  if (options.csv) {
    csv = std::make_unique<util::AtomicFile>(*options.csv);
    r.csv = *options.csv;
    rows += util::kStateCsvHeader;
  }

  std::unique_ptr<util::AtomicFile> contacts_csv;
  std::string contact_rows;
  if (options.contacts_csv) {
    contacts_csv = std::make_unique<util::AtomicFile>(*options.contacts_csv);
    contact_rows += kContactCsvHeader;
  }

  rigid::StateFrame frame;
  common::shape_state_frame(driven.world(), frame);
  const int bodies = driven.world().body_count();
  rigid::ContactEvents contacts;
  const ContactNames contact_names(describe_scene(scene, driven.world()));
  // The tick whose contact events the replay has and the journal has not confirmed yet: rigidd
  // journals a tick's contact hash right after its steps, before anything else of that tick, so
  // such events must be confirmed before the replay steps again or reads another record.
  std::optional<std::int64_t> unconfirmed;
  auto events_confirmed = [&](std::int64_t tick) {
    if (!unconfirmed) return true;
    r.divergence = ReplayReport::Divergence{
        *unconfirmed, 0, 0,
        "the replay's tick " + std::to_string(*unconfirmed) + " has " +
            std::to_string(driven.world().contact_events().size()) +
            " contact event(s), the journal none (next journaled entry at tick " +
            std::to_string(tick) + ")"};
    return false;
  };
  // Steps the replay to `tick`; false (and a divergence) if the journal goes back in time, which
  // the live loop never does between resets, or if a tick has contact events the journal lacks.
  auto advance_to = [&](std::int64_t tick, const char* what) {
    if (tick < driven.tick()) {
      r.divergence = ReplayReport::Divergence{
          tick, 0, 0,
          std::string("a ") + what + " at tick " + std::to_string(tick) + " comes after tick " +
              std::to_string(driven.tick()) + " (journal out of order)"};
      return false;
    }
    for (; driven.tick() < tick; ++r.ticks) {
      if (!events_confirmed(tick)) return false;
      driven.step_tick();
      if (!driven.world().contact_events().empty()) unconfirmed = driven.tick();
    }
    return true;
  };

  msgs::LogRecord record;
  rigid::AcceptedCommand accepted;
  while (!r.divergence && !r.gap && reader.next(record)) {
    switch (record.record_case()) {
      case msgs::LogRecord::kCommand: {
        common::from_record(record.command(), accepted);
        if (!advance_to(accepted.tick, "command") || !events_confirmed(accepted.tick)) break;
        if (accepted.kind == rigid::AcceptedKind::kWrench) {
          ++r.wrenches;
          const Wrench w = wrench_of(accepted);
          if (w.body < 0 || w.body >= bodies) {
            r.divergence = ReplayReport::Divergence{
                accepted.tick, 0, 0,
                "a wrench on body " + std::to_string(w.body) + ", which the scene does not have"};
          } else if (driven.apply(w) == common::WrenchTable::Upsert::kFull) {
            r.divergence = ReplayReport::Divergence{
                accepted.tick, 0, 0,
                "a wrench rigidd accepted finds the replay's wrench table full (" +
                    std::to_string(capacity) + " entries)"};
          }
        } else if (accepted.kind == rigid::AcceptedKind::kEdit) {
          ++r.edits;
          const Edit e = edit_of(accepted);
          // rigidd validated it; a journal written by hand (or damaged in a way the checksums
          // missed) could still name a body the scene lacks, or a state set_state refuses.
          const auto& q = e.orientation;
          const bool sets_orientation = (e.set & rigid::kSetOrientation) != 0;
          if (e.body < 0 || e.body >= bodies ||
              (e.kind != rigid::EditKind::kSetState && e.kind != rigid::EditKind::kResetBody) ||
              (sets_orientation &&
               !(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3] > 0.5))) {
            r.divergence = ReplayReport::Divergence{
                accepted.tick, 0, 0,
                "an edit (" + std::string(rigid::edit_name(e.kind)) + ") on body " +
                    std::to_string(e.body) + " that this scene cannot take"};
          } else {
            try {
              driven.edit(e);
            } catch (const std::invalid_argument& error) {
              r.divergence = ReplayReport::Divergence{accepted.tick, 0, 0,
                                                      std::string("an edit: ") + error.what()};
            }
          }
        } else {
          ++r.controls;
          if (accepted.command == rigid::ControlKind::kReset) {
            driven.reset();
            ++r.resets;
          }
        }
        break;
      }
      case msgs::LogRecord::kStateHash: {
        const std::int64_t tick = record.state_hash().tick();
        if (!advance_to(tick, "state hash") || !events_confirmed(tick)) break;
        common::fill_state_frame(driven.world(), tick, static_cast<double>(tick) * tick_dt, frame);
        const std::uint64_t replayed = common::state_hash(frame);
        ++r.hashes_compared;
        if (replayed != record.state_hash().hash()) {
          r.divergence = ReplayReport::Divergence{tick, record.state_hash().hash(), replayed,
                                                  "state hash mismatch"};
          break;
        }
        r.last_verified_tick = tick;
        if (on_state) on_state(frame);
        if (csv) {
          append_state_rows(driven.world(), rows);
          r.csv_rows += bodies;
          if (rows.size() >= (1 << 20)) {
            csv->write(rows);
            rows.clear();
          }
        }
        break;
      }
      case msgs::LogRecord::kContactHash: {
        const msgs::ContactHash& h = record.contact_hash();
        if (!advance_to(h.tick(), "contact hash")) break;
        if (unconfirmed != h.tick()) {
          r.divergence = ReplayReport::Divergence{
              h.tick(), h.hash(), 0,
              "the journal has " + std::to_string(h.events()) + " contact event(s) at tick " +
                  std::to_string(h.tick()) + ", the replay none"};
          break;
        }
        common::fill_contact_events(driven.world().contact_events(), h.tick(),
                                    static_cast<double>(h.tick()) * tick_dt, contacts);
        const std::uint64_t replayed = common::contact_hash(contacts);
        if (replayed != h.hash()) {
          r.divergence = ReplayReport::Divergence{
              h.tick(), h.hash(), replayed,
              "contact events hash mismatch (journal " + std::to_string(h.events()) +
                  " event(s), replay " + std::to_string(contacts.event_count()) + ")"};
          break;
        }
        unconfirmed.reset();
        ++r.contact_hashes_compared;
        r.contact_events += static_cast<std::int64_t>(contacts.event_count());
        if (on_contacts) on_contacts(contacts);
        if (contacts_csv) {
          append_contact_rows(contacts, contact_names, contact_rows);
          if (contact_rows.size() >= (1 << 20)) {
            contacts_csv->write(contact_rows);
            contact_rows.clear();
          }
        }
        break;
      }
      case msgs::LogRecord::kGap:
        r.gap = ReplayReport::Gap{record.gap().tick(), record.gap().dropped()};
        break;
      case msgs::LogRecord::kEnd:
        r.closed_cleanly = true;
        break;
      default:
        break;  // a record kind this replay has no use for
    }
  }
  if (reader.damage()) {
    r.damage = "offset " + std::to_string(reader.damage()->offset) + ", " +
               std::to_string(reader.damage()->bytes) + " bytes: " + reader.damage()->reason;
  }
  if (csv) {
    csv->write(rows);
    csv->commit();
  }
  if (contacts_csv) {
    contacts_csv->write(contact_rows);
    contacts_csv->commit();
  }
  return r;
}

void print_replay(std::ostream& out, const ReplayReport& r) {
  out << "replay of " << r.journal << " (written by " << r.software_version << ")\n"
      << "scene " << r.scene << ", " << r.rate_hz << " Hz, integrator " << r.integrator << '\n'
      << r.ticks << " ticks, " << r.wrenches << " wrenches, " << r.controls << " controls ("
      << r.resets << " resets), " << r.edits << " edits, " << r.hashes_compared
      << " state hashes compared";
  if (r.contact_hashes_compared > 0) {
    out << ", " << r.contact_events << " contact events in " << r.contact_hashes_compared
        << " ticks compared";
  }
  out << '\n';
  if (!r.damage.empty()) {
    out << "the journal ends in a damaged tail (" << r.damage
        << "): rigidd stopped without closing it; everything before it was replayed\n";
  } else if (!r.closed_cleanly && !r.divergence && !r.gap) {
    out << "the journal has no closing record: rigidd stopped without closing it\n";
  }
  if (!r.csv.empty()) out << "csv: " << r.csv << ", " << r.csv_rows << " rows\n";
  if (r.divergence) {
    const ReplayReport::Divergence& d = *r.divergence;
    out << "DIVERGED at tick " << d.tick << ": " << d.what;
    if (d.journaled != 0 || d.replayed != 0) {
      out << " (journal " << hex(d.journaled) << ", replay " << hex(d.replayed) << ")";
    }
    out << "; last identical state at tick " << r.last_verified_tick << '\n';
  } else if (r.gap) {
    out << "INCOMPLETE: rigidd lost " << r.gap->dropped << " journal entries before tick "
        << r.gap->tick << "; verified up to tick " << r.last_verified_tick << '\n';
  } else {
    out << "identical: every journaled state"
        << (r.contact_hashes_compared > 0 ? " and contact event" : "")
        << " reproduced bit for bit (last at tick " << r.last_verified_tick << ")\n";
  }
}

}  // namespace rigid::common
