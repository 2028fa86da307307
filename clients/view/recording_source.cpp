#include "recording_source.hpp"

#include <algorithm>
#include <iterator>
#include <map>
#include <utility>

#include "cli/cli.hpp"
#include "common/lcm_log.hpp"
#include "common/log_records.hpp"
#include "common/record_file.hpp"
#include "common/replay.hpp"
#include "common/state_conversion.hpp"
#include "drift.hpp"
#include "physics/world.hpp"
#include "protocol.hpp"
#include "scene/scene.hpp"
#include "transport/lcm/lcm_codec.hpp"
#include "transport/topic.hpp"

namespace rigid::view {
namespace {

constexpr std::size_t kMaxPrefixes = 256;  // of rigidd's channels in one lcm-logger log

std::string megabytes(std::size_t bytes) {
  return std::to_string((bytes + (1u << 20) - 1) >> 20) + " MiB";
}

std::string damage_note(const common::Damage& d) {
  return "played up to a damaged tail at offset " + std::to_string(d.offset) + " (" + d.reason +
         "), " + std::to_string(d.bytes) + " bytes not read";
}

// For a recording too large for memory.
std::string play_elsewhere(const std::string& path) {
  return "play it with `rigid-record play " + path + "` and watch it with a live rigid-view";
}

// Adds states in file order: encodes each once, places it on the timeline and keeps the total
// under the limit.
class Builder {
 public:
  // elsewhere: where to play a file too large for memory. states_place_wrenches: the states
  // added are the ones the commands interleave with in the file (a journal's states come from its
  // replay instead: its StateHash records place its commands, journal_wrenches).
  Builder(Recording& r, const LoadLimits& limits, std::string elsewhere,
          bool states_place_wrenches = true)
      : r_(r),
        limits_(limits),
        elsewhere_(std::move(elsewhere)),
        states_place_wrenches_(states_place_wrenches) {}

  // A scene that differs from the one in force (LCM repeats SceneInfo every second).
  void scene(const SceneDescription& d) {
    if (!r_.scenes.empty() && r_.scenes.back() == d) return;
    if (!r_.scenes.empty() && r_.states.empty()) {  // replaced before any state used it
      r_.scenes.back() = d;
      return;
    }
    if (!r_.scenes.empty() && states_place_wrenches_) r_.wrenches.scene_changed();
    r_.scenes.push_back(d);
    drift_.set_scene(d);
  }

  // An accepted command, in file order (only wrenches, resets and edits matter to the arrows and
  // the drifts).
  void command(const AcceptedCommand& a) {
    if (a.kind == AcceptedKind::kEdit) {
      // An edit changes its body's energy and momentum: not drift (nor does it cost memory).
      if (states_place_wrenches_) drive(a.body_id, a.tick, 0.0);
      r_.wrenches.command(a, r_.scenes.empty() ? 0.0 : r_.scenes.back().dt);
      return;
    }
    if (a.kind != AcceptedKind::kWrench &&
        !(a.kind == AcceptedKind::kControl && a.command == ControlKind::kReset))
      return;
    // The wrench, and its key in the table that finds the one it replaces (a map node).
    const std::size_t cost = sizeof(RecordedWrench) + 96;
    if (r_.bytes + cost > limits_.max_bytes) {
      throw RecordingError(
          r_.path + ": its states and accepted commands need more than " +
          megabytes(limits_.max_bytes) + " in memory (" + std::to_string(r_.wrenches.all().size()) +
          " wrenches read so far; --max-memory raises the limit, or " + elsewhere_ + ")");
    }
    r_.bytes += cost;
    r_.wrenches.command(a, r_.scenes.empty() ? 0.0 : r_.scenes.back().dt);
    if (states_place_wrenches_ && a.kind == AcceptedKind::kWrench) drive(a.body_id, a.tick, a.ttl);
  }

  // A wrench's body is driven from its tick (drift.hpp): its work is not drift. A recording's
  // commands are read with its states (a command usually before the states it acts on: rigidd
  // publishes it when it accepts it); a journal's are given by from_journal before the states
  // they precede.
  void drive(std::int32_t body, std::int64_t tick, double ttl) { drift_.drive(body, tick, ttl); }

  // `s` is the reader's frame: its stamp is cleared (see below).
  void state(StateFrame& s) {
    // A state before any scene (an LCM log: SceneInfo comes once a second) takes the first one.
    const std::uint32_t scene =
        r_.scenes.empty() ? 0 : static_cast<std::uint32_t>(r_.scenes.size() - 1);
    // The stamp (rigidd's wall clock at publish) is what the page measures its latency from; a
    // recording's stamps are from when it was made: 0 says there is none to measure.
    s.stamp_ns = 0;
    drift_.update(s);
    auto frame = std::make_shared<const std::string>(
        encode_state(s, Recording::generation(scene), drift_.energy(), drift_.momentum()));
    // The frame, its string and shared_ptr (with its control block, about as big), its index entry.
    const std::size_t cost = frame->size() + sizeof(std::string) +
                             2 * sizeof(std::shared_ptr<const std::string>) + sizeof(RecordedState);
    if (r_.bytes + cost > limits_.max_bytes) {
      throw RecordingError(r_.path + ": its states need more than " + megabytes(limits_.max_bytes) +
                           " in memory (" + std::to_string(r_.states.size()) +
                           " states read so far; --max-memory raises the limit, or " + elsewhere_ +
                           ")");
    }
    r_.bytes += cost;
    // Where the recording goes back in sim time (a reset), the timeline carries on from the
    // previous position: position = sim time + offset of the current stretch.
    if (!r_.states.empty() && s.sim_time < r_.states.back().sim_time)
      offset_ = r_.states.back().position - s.sim_time;
    if (!r_.states.empty() && s.tick < r_.states.back().tick) ++stretch_;
    if (states_place_wrenches_) r_.wrenches.state(s.tick);
    r_.states.push_back(RecordedState{s.tick, s.sim_time, s.sim_time + offset_, scene, stretch_});
    r_.frames.push_back(std::move(frame));
  }

  void stats(const StatsReport& s) {
    auto text = std::make_shared<const std::string>(stats_json(s));
    const std::size_t cost = text->size() + sizeof(Recording::Stats) + 2 * sizeof(std::string);
    if (r_.bytes + cost > limits_.max_bytes) return;  // the states' limit reports it
    r_.bytes += cost;
    if (!r_.stats.empty() && r_.stats.back().first_state == r_.states.size()) {
      r_.stats.back().text = std::move(text);  // two before the same state: the later one counts
    } else {
      r_.stats.push_back(Recording::Stats{r_.states.size(), std::move(text)});
    }
  }

 private:
  Recording& r_;
  const LoadLimits& limits_;
  std::string elsewhere_;
  bool states_place_wrenches_;
  double offset_ = 0;
  std::uint32_t stretch_ = 0;
  DriftTracker drift_;  // each state's drifts, computed once here as live mode computes them
};

// A journal's commands, placed by its StateHash records (the states rigidd published, in the
// order it journaled them with its commands: exactly the order of the replay's states).
void journal_wrenches(const std::string& path, Builder& add, Recording& r) {
  common::RecordReader reader(path);
  msgs::LogRecord record;
  AcceptedCommand a;
  while (reader.next(record)) {
    if (record.has_state_hash()) {
      r.wrenches.state(record.state_hash().tick());
    } else if (record.has_command()) {
      common::from_record(record.command(), a);
      add.command(a);
    }
  }
}

// The scene the page draws: the SceneInfo rigidd published, which it keeps in the journal's
// header; a journal without one (not rigidd's) is described from its copy of the scene file, as
// rigidd would have described it.
SceneDescription journal_scene(const std::string& path, const msgs::LogHeader& h) {
  SceneDescription d;
  if (h.has_scene() && !h.scene().ids().empty()) {
    if (!common::from_record(h.scene(), d))
      throw RecordingError(path + ": the header's scene has per-body arrays that disagree");
    return d;
  }
  if (h.scene_text().empty())
    throw RecordingError(path + ": a journal that holds no scene: nothing to draw");
  const scene::Scene s = scene::parse_scene(h.scene_text(), path + ":scene");
  return common::describe_scene(s, physics::World(s.world));
}

// A journal holds the scene and the accepted commands, no states: rigid-sim's replay re-steps the
// world and checks each state against the hash rigidd journaled. Only the states it verified are
// kept, and a journal that diverges is refused whole: the page never shows a state rigidd did not
// publish.
void from_journal(Recording& r, const msgs::LogHeader& header, const LoadLimits& limits) {
  r.kind = "rigidd journal, replayed";
  // rigid-record play needs states: a journal's come from rigid-sim.
  Builder add(r, limits, "write its states with `rigid-sim --replay " + r.path + " --csv OUT`",
              false);
  common::ReplayOptions o;
  o.journal = r.path;
  StateFrame frame;  // the replay's frame is const; Builder clears the stamp of its own copy
  common::ReplayReport report;
  try {
    add.scene(journal_scene(r.path, header));
    // The wrenches, each with the number of published states journaled before it: it drives its
    // body from the state after those (drift.hpp).
    struct Drive {
      std::size_t before_state;
      std::int32_t body;
      std::int64_t tick;
      double ttl;
    };
    std::vector<Drive> drives;
    {
      common::RecordReader reader(r.path);
      msgs::LogRecord record;
      std::size_t hashes = 0;
      AcceptedCommand a;
      while (reader.next(record)) {
        if (record.has_state_hash()) {
          ++hashes;
        } else if (record.has_command()) {
          common::from_record(record.command(), a);
          // A wrench drives its body for its ttl; an edit for the tick it was made at.
          if (a.kind != AcceptedKind::kWrench && a.kind != AcceptedKind::kEdit) continue;
          if ((drives.size() + 1) * sizeof(Drive) > limits.max_bytes) {
            throw RecordingError(r.path + ": its wrenches need more than " +
                                 megabytes(limits.max_bytes) +
                                 " in memory (--max-memory raises the limit)");
          }
          drives.push_back(Drive{hashes, a.body_id, a.tick, a.ttl});
        }
      }
    }
    std::size_t states = 0, next_drive = 0;
    report = common::replay(o, [&](const StateFrame& s) {
      for (; next_drive < drives.size() && drives[next_drive].before_state <= states; ++next_drive)
        add.drive(drives[next_drive].body, drives[next_drive].tick, drives[next_drive].ttl);
      ++states;
      frame = s;
      add.state(frame);
    });
    journal_wrenches(r.path, add, r);
  } catch (const RecordingError&) {
    throw;  // the memory limit, or the header's scene: already one line naming the file
  } catch (const std::exception& e) {
    // An unreadable journal, a bad copy of the scene: what() says which.
    throw RecordingError(r.path + ": cannot replay it: " + e.what());
  }
  const auto add_note = [&r](const std::string& text) {
    r.note += (r.note.empty() ? "" : "; ") + text;
  };
  for (const std::string& w : report.warnings)
    add_note(w);  // e.g. another build of rigidd: its states were verified all the same
  if (report.divergence) {
    const common::ReplayReport::Divergence& d = *report.divergence;
    throw RecordingError(r.path + ": the replay does not reproduce it: DIVERGED at tick " +
                         std::to_string(d.tick) + " (" + d.what + ")" +
                         (r.note.empty() ? "" : "; " + r.note) +
                         "; nothing played (`rigid-sim --replay " + r.path + "` says more)");
  }
  if (report.gap) {
    add_note("rigidd lost " + std::to_string(report.gap->dropped) +
             " journal entries before tick " + std::to_string(report.gap->tick) +
             ": played the states verified up to tick " +
             std::to_string(report.last_verified_tick));
  } else if (!report.damage.empty()) {
    add_note("played up to a damaged tail (" + report.damage + ")");
  } else if (!report.closed_cleanly) {
    add_note("the journal has no closing record (rigidd stopped without closing it)");
  }
}

void from_rigid_log(Recording& r, const LoadLimits& limits) {
  common::RecordReader reader(r.path);
  msgs::LogRecord record;
  if (!reader.next(record) || !record.has_header()) {
    throw RecordingError(r.path + ": no header record" +
                         (reader.damage() ? " (" + reader.damage()->reason + ")" : std::string()));
  }
  if (record.header().kind() == msgs::LogHeader::JOURNAL) {
    from_journal(r, record.header(), limits);
    return;
  }
  if (record.header().kind() != msgs::LogHeader::RECORDING)
    throw RecordingError(r.path + ": not a recording (rigid-record info says what it is)");
  r.kind = "rigid-record recording";
  Builder add(r, limits, play_elsewhere(r.path));
  SceneDescription scene;
  if (!common::from_record(record.header().scene(), scene))
    throw RecordingError(r.path + ": the header's scene has per-body arrays that disagree");
  add.scene(scene);
  StateFrame frame;
  StatsReport stats;
  AcceptedCommand accepted;
  while (reader.next(record)) {
    if (record.has_command()) {
      common::from_record(record.command(), accepted);
      add.command(accepted);
    } else if (record.has_stats()) {
      common::from_record(record.stats(), stats);
      add.stats(stats);
    } else if (record.has_scene()) {
      if (!common::from_record(record.scene(), scene)) {
        throw RecordingError(r.path + ": record " + std::to_string(reader.records()) +
                             ": a scene whose per-body arrays disagree");
      }
      add.scene(scene);
    } else if (record.has_state()) {
      if (!common::from_record(record.state(), frame)) {
        throw RecordingError(r.path + ": record " + std::to_string(reader.records()) +
                             ": a state whose arrays disagree with its body count");
      }
      add.state(frame);
    }
  }
  if (reader.damage()) r.note = damage_note(*reader.damage());
}

void from_lcm_log(Recording& r, const LoadLimits& limits) {
  r.kind = "lcm-logger log";
  // The state channels the log holds (rigid-record's prefix rule looks at nothing else), at most
  // kMaxPrefixes of them: other channels are not kept, so a log of many channels costs nothing.
  const std::string plain_state =
      transport::lcm_channel_names("")[transport::index_of(transport::Topic::kState)];
  std::map<std::string, std::int64_t> seen;  // channel -> events
  {
    common::LcmLogReader reader(r.path);
    common::LcmEvent event;
    while (reader.next(event)) {
      if (!event.channel.ends_with(plain_state)) continue;
      if (!seen.contains(event.channel) && seen.size() >= kMaxPrefixes) {
        throw RecordingError(r.path + ": more than " + std::to_string(kMaxPrefixes) +
                             " prefixes of " + plain_state + " channels in this log");
      }
      ++seen[event.channel];
    }
  }
  const transport::TopicNames names = transport::lcm_channel_names(common::lcm_log_prefix(
      r.path,
      limits.lcm_prefix_given ? std::optional<std::string>(limits.lcm_prefix) : std::nullopt,
      seen));
  const std::string& state_channel = names[transport::index_of(transport::Topic::kState)];
  const std::string& scene_channel = names[transport::index_of(transport::Topic::kScene)];
  const std::string& stats_channel = names[transport::index_of(transport::Topic::kStats)];
  const std::string& accepted_channel = names[transport::index_of(transport::Topic::kAccepted)];
  transport::lcm::Codec codec;
  Builder add(r, limits, play_elsewhere(r.path));
  common::LcmLogReader reader(r.path);
  common::LcmEvent event;
  SceneDescription scene;
  StateFrame frame;
  StatsReport stats;
  AcceptedCommand accepted;
  std::int64_t undecodable = 0;
  while (reader.next(event)) {
    if (event.channel == accepted_channel) {
      if (codec.decode(event.data, accepted) == transport::DecodeStatus::kOk) {
        add.command(accepted);
      } else {
        ++undecodable;
      }
    } else if (event.channel == stats_channel) {
      if (codec.decode(event.data, stats) == transport::DecodeStatus::kOk) {
        add.stats(stats);
      } else {
        ++undecodable;
      }
    } else if (event.channel == scene_channel) {
      if (codec.decode(event.data, scene) == transport::DecodeStatus::kOk) {
        add.scene(scene);
      } else {
        ++undecodable;
      }
    } else if (event.channel == state_channel) {
      if (codec.decode(event.data, frame) == transport::DecodeStatus::kOk) {
        add.state(frame);
      } else {
        ++undecodable;
      }
    }
  }
  if (reader.damage()) r.note = damage_note(*reader.damage());
  if (undecodable > 0) {
    r.note += (r.note.empty() ? "" : "; ") + std::to_string(undecodable) + " events on " +
              state_channel + ", " + scene_channel + ", " + stats_channel + " or " +
              accepted_channel + " did not decode and were skipped";
  }
  if (r.scenes.empty())
    throw RecordingError(r.path + ": no SceneInfo on " + scene_channel + ": nothing to draw");
}

}  // namespace

std::shared_ptr<const std::string> Recording::stats_at(std::size_t i) const {
  // The last Stats whose first state is at or before i.
  const auto after =
      std::upper_bound(stats.begin(), stats.end(), i,
                       [](std::size_t state, const Stats& s) { return state < s.first_state; });
  return after == stats.begin() ? nullptr : std::prev(after)->text;
}

std::vector<std::size_t> Recording::wrenches_at(std::size_t i) const {
  if (i >= states.size()) return {};
  return wrenches.acting(states[i].stretch, states[i].tick, kMaxWrenchesShown);
}

Recording load_recording(const std::string& path, const LoadLimits& limits) {
  Recording r;
  r.path = path;
  try {
    if (common::looks_like_lcm_log(path)) {
      from_lcm_log(r, limits);
    } else {
      from_rigid_log(r, limits);
    }
  } catch (const common::LogFileError& e) {
    throw RecordingError(e.what());
  } catch (const clients::UsageError& e) {
    throw RecordingError(e.what());
  }
  if (r.states.empty()) {
    throw RecordingError(path + ": no states to play" +
                         (r.note.empty() ? std::string() : " (" + r.note + ")"));
  }
  r.wrenches.finish(r.scenes.empty() ? 0.0 : r.scenes.front().dt);
  return r;
}

}  // namespace rigid::view
