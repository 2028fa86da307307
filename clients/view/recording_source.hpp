// rigid-view FILE: a recording loaded for the page, read with rigid-record's readers (a
// rigid-record recording through common::RecordReader, an lcm-logger log through
// common::LcmLogReader), or a journal of rigidd (rigidd --journal), which holds no states: they
// are re-stepped by the replay rigid-sim runs (common/replay.hpp) and only those whose hash matches
// the journal's are kept, which are the states rigidd published. Every state is kept in memory
// already encoded as the page's binary frame (protocol.hpp encode_state), so that playing and
// seeking cost a lookup and no encoding (with stamp 0: the recorded stamps say nothing of the
// page's latency). Memory is bounded: a file whose frames would need more than
// LoadLimits::max_bytes is refused with one line naming the file and the size (play such a file on
// a bus with `rigid-record play` and watch it with a live rigid-view; a journal's states go to CSV
// with `rigid-sim --replay`).
//
// The timeline: each state has a position on it, its sim time, except that a recording which goes
// back in sim time (rigidd reset while recording) carries on from where it was, so that positions
// never decrease and a seek by time has one answer. Without a reset, position == sim time exactly.
//
// The accepted wrenches (a recording's and an lcm-logger log's accepted-command stream, a
// journal's commands) are kept too, with the states they act on (recorded_wrenches.hpp), so that
// playback draws the arrows live mode draws.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "recorded_wrenches.hpp"
#include "rigid/messages.hpp"

namespace rigid::view {

// A file that cannot be played: what() is one line naming the file and the reason.
class RecordingError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct LoadLimits {
  std::size_t max_bytes = std::size_t{512} << 20;  // of encoded frames and their index
  std::string lcm_prefix;                          // lcm-logger logs: the channels' prefix
  bool lcm_prefix_given = false;                   // else the one the log holds
};

struct RecordedState {
  std::int64_t tick = 0;
  double sim_time = 0;
  double position = 0;      // on the timeline (see above)
  std::uint32_t scene = 0;  // index into Recording::scenes
  // Counts the places before it where the tick went back (a reset, a restarted rigidd): a
  // wrench's tick means something within its stretch only (recorded_wrenches.hpp).
  std::uint32_t stretch = 0;
};

struct Recording {
  std::string path;
  std::string kind;  // "rigid-record recording", "lcm-logger log", "rigidd journal, replayed"
  std::vector<SceneDescription> scenes;  // in order; a state names the one in force
  std::vector<RecordedState> states;     // in file order; positions do not decrease
  // frames[i]: states[i] as encode_state wrote it, shared with the pages it is being sent to.
  std::vector<std::shared_ptr<const std::string>> frames;
  // rigidd's Stats as the page's HUD reads them (stats_json), each with the index of the first
  // state after it: shown with that state and those until the next.
  struct Stats {
    std::size_t first_state = 0;
    std::shared_ptr<const std::string> text;
  };
  std::vector<Stats> stats;
  RecordedWrenches wrenches;  // the accepted wrenches, by the states they act on
  std::size_t bytes = 0;      // what the frames, the index and the wrenches hold
  std::string note;           // how the file ended when not cleanly, else ""

  // The scene generation the page sees for scenes[k] (1, 2, ...): states carry it.
  static std::uint32_t generation(std::uint32_t scene) { return scene + 1; }
  // The Stats in force at state i (the last one recorded before it), or null.
  std::shared_ptr<const std::string> stats_at(std::size_t i) const;
  // The wrenches acting on state i (the newest last, at most kMaxWrenchesShown), as indices into
  // wrenches.all().
  std::vector<std::size_t> wrenches_at(std::size_t i) const;
};

// Reads `path` whole (a journal: replays it whole). Throws RecordingError: unreadable, not a
// recording, no scene or no state, a state whose arrays disagree with its body count, larger than
// limits.max_bytes (states and wrenches), or a journal whose replay diverges (or cannot run: no
// scene, a bad one). A damaged tail (a recorder or rigidd killed mid-write) is not an error: the
// states before it are kept and `note` says where the file stopped being readable; so is a
// journal's gap (entries rigidd lost), up to which its states are verified and kept.
Recording load_recording(const std::string& path, const LoadLimits& limits);

}  // namespace rigid::view
