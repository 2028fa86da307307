#include "record/log_info.hpp"

#include <algorithm>
#include <cstdio>
#include <ctime>
#include <map>
#include <ostream>

#include "cli/cli.hpp"
#include "common/lcm_log.hpp"
#include "common/record_file.hpp"

namespace rigid::record {
namespace {

std::string utc(std::int64_t unix_ns) {
  const std::time_t t = static_cast<std::time_t>(unix_ns / 1'000'000'000);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buffer[64];
  std::strftime(buffer, sizeof buffer, "%Y-%m-%d %H:%M:%S UTC", &tm);
  return buffer;
}

std::string seconds(double s) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3f s", s);
  return buffer;
}

// A scene's body names for one line: all of them up to kShown, else the first few and the last
// (a recording of 1000 bodies would otherwise print 1000 names on one line).
std::string name_summary(const google::protobuf::RepeatedPtrField<std::string>& names) {
  constexpr int kShown = 8;
  std::string text;
  const int n = names.size();
  for (int i = 0; i < n; ++i) {
    if (n > kShown && i == kShown - 2) {
      text += ", ... " + std::to_string(n - kShown + 1) + " more ..., " + names[n - 1];
      break;
    }
    text += (i == 0 ? "" : ", ") + names[i];
  }
  return text;
}

std::string damage_line(const common::Damage& d) {
  return "damaged tail at offset " + std::to_string(d.offset) + ": " + std::to_string(d.bytes) +
         " bytes not read (" + d.reason +
         "); everything before it is intact (a writer stopped mid-record leaves this)";
}

int lcm_info(const std::string& path, std::ostream& out) {
  common::LcmLogReader reader(path);
  std::map<std::string, std::int64_t> channels;
  std::int64_t first_us = 0, last_us = 0;
  common::LcmEvent e;
  while (reader.next(e)) {
    if (reader.events() == 1) first_us = e.timestamp_us;
    last_us = e.timestamp_us;
    ++channels[e.channel];
  }
  out << path << ": an lcm-logger log, " << reader.events() << " events over "
      << seconds(static_cast<double>(last_us - first_us) * 1e-6) << '\n';
  for (const auto& [channel, n] : channels)
    out << "  " << channel << ": " << n << '\n';
  out << (reader.damage() ? damage_line(*reader.damage()) : "ends after a complete event") << '\n';
  return clients::kExitOk;
}

}  // namespace

int info(const std::string& path, std::ostream& out, std::ostream& err) {
  try {
    if (common::looks_like_lcm_log(path)) return lcm_info(path, out);
    common::RecordReader reader(path);
    msgs::LogRecord r;
    struct Span {
      std::int64_t first = -1, last = -1;
      void see(std::int64_t t) {
        if (first < 0) first = t;
        last = t;
      }
    };
    std::int64_t states = 0, scenes = 0, stats = 0, wrenches = 0, controls = 0, resets = 0,
                 hashes = 0, gaps = 0, unknown = 0, contact_ticks = 0, contact_events = 0,
                 contact_hashes = 0;
    Span ticks, recorded;
    double sim_first = 0, sim_last = 0;
    std::optional<msgs::LogEnd> end;
    std::optional<msgs::LogHeader> header;
    while (reader.next(r)) {
      switch (r.record_case()) {
        case msgs::LogRecord::kHeader:
          if (!header) header = r.header();
          break;
        case msgs::LogRecord::kState:
          if (states++ == 0) sim_first = r.state().sim_time();
          sim_last = r.state().sim_time();
          ticks.see(r.state().tick());
          recorded.see(r.state().recorded_ns());
          break;
        case msgs::LogRecord::kScene:
          ++scenes;
          break;
        case msgs::LogRecord::kStats:
          ++stats;
          break;
        case msgs::LogRecord::kCommand:
          if (r.command().kind() == msgs::CommandRecord::CONTROL) {
            ++controls;
            resets += r.command().command() == 4;  // CONTROL_RESET of msgs/rigid.idl
          } else {
            ++wrenches;
          }
          break;
        case msgs::LogRecord::kStateHash:
          ++hashes;
          ticks.see(r.state_hash().tick());
          break;
        case msgs::LogRecord::kContacts:
          ++contact_ticks;
          contact_events += r.contacts().kinds_size();
          break;
        case msgs::LogRecord::kContactHash:
          ++contact_hashes;
          contact_events += r.contact_hash().events();
          break;
        case msgs::LogRecord::kGap:
          ++gaps;
          break;
        case msgs::LogRecord::kEnd:
          end = r.end();
          break;
        default:
          ++unknown;
          break;
      }
    }
    out << path << ": rigid log (format " << reader.format()
        << (reader.format() == common::kLogFormatChunked ? ", zstd chunks" : "") << "), "
        << reader.size() << " bytes, " << reader.records() << " complete records";
    if (reader.chunks() > 0) {
      char ratio[160];
      std::snprintf(ratio, sizeof ratio,
                    " (%lld chunks: %.2f MB of records compressed to %.2f MB, ratio %.2f)",
                    static_cast<long long>(reader.chunks()),
                    static_cast<double>(reader.chunk_record_bytes()) / 1e6,
                    static_cast<double>(reader.chunk_bytes()) / 1e6,
                    static_cast<double>(reader.chunk_record_bytes()) /
                        static_cast<double>(std::max<std::uint64_t>(1, reader.chunk_bytes())));
      out << ratio;
    }
    out << '\n';
    if (!header) {
      out << "no header record: not written by rigid-record or rigidd\n";
    } else {
      const msgs::LogHeader& h = *header;
      const bool journal = h.kind() == msgs::LogHeader::JOURNAL;
      out << (journal ? "journal" : "recording") << " written by " << h.writer() << " ("
          << h.software_version() << ", schema " << h.schema_version() << "), started "
          << utc(h.start_unix_ns()) << '\n';
      const msgs::SceneRecord& s = h.scene();
      const std::string names = name_summary(s.names());
      char rate[160];
      std::snprintf(rate, sizeof rate, "%g Hz, %d substep(s), a state every %d tick(s)",
                    h.rate_hz(), s.substeps(), s.publish_every());
      out << "scene " << s.scene_name() << ": " << s.names_size() << " bodies (" << names << "), "
          << rate << ", integrator " << h.integrator() << '\n';
      if (journal) {
        out << "mode " << h.mode() << ", wrench table " << h.wrench_capacity()
            << " entries, scene text " << h.scene_text().size() << " bytes kept\n";
      } else {
        out << "recorded from " << h.transport() << " " << h.address()
            << (h.prefix().empty() ? "" : ", prefix " + h.prefix()) << '\n';
      }
    }
    out << "records: " << states << " states, " << scenes << " scenes, " << stats << " stats, "
        << wrenches + controls << " accepted commands (" << wrenches << " wrenches, " << controls
        << " controls, " << resets << " resets), " << hashes << " state hashes, " << gaps
        << " gaps";
    if (contact_ticks > 0 || contact_hashes > 0) {
      out << ", " << contact_events << " contact events in " << contact_ticks + contact_hashes
          << (contact_hashes > 0 ? " hashed" : "") << " ticks";
    }
    if (unknown > 0) out << ", " << unknown << " of kinds this version does not know";
    out << '\n';
    if (states > 0) {
      out << "states: ticks " << ticks.first << " .. " << ticks.last
          << " (t = " << seconds(sim_first) << " .. " << seconds(sim_last) << "), recorded over "
          << seconds(static_cast<double>(recorded.last - recorded.first) * 1e-9) << '\n';
    } else if (hashes > 0) {
      out << "state hashes: ticks " << ticks.first << " .. " << ticks.last << '\n';
    }
    if (gaps > 0) {
      out << "the writer lost entries (" << gaps << " gap(s)): a replay stops at the first\n";
    }
    if (reader.damage()) {
      out << damage_line(*reader.damage()) << '\n';
    } else if (end) {
      out << "ends cleanly";
      if (end->dropped() > 0) out << " (" << end->dropped() << " messages dropped while writing)";
      out << '\n';
    } else {
      out << "no closing record: the writer stopped without closing the file (killed?); every "
             "record in it is complete\n";
    }
    return clients::kExitOk;
  } catch (const common::LogFileError& e) {
    err << "rigid-record: " << e.what() << '\n';
    return clients::kExitFailed;
  }
}

}  // namespace rigid::record
