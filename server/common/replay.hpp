// rigid-sim --replay: re-runs a session rigidd journaled (rigidd --journal) and checks that it
// reproduces it bit for bit. Each journaled command (wrench, control, edit) is applied at the tick
// at which it took effect live, through the loop's own DrivenWorld (the same wrench table, order of
// summation and expiry, the same edits as the live loop), and each journaled state hash is
// compared with the hash of the state the replay reaches at that tick, and each contact hash with
// the hash of the contact events of that tick. The first mismatch is the divergence, reported with
// its tick.
#pragma once

#include <cstdint>
#include <functional>
#include <iosfwd>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "rigid/messages.hpp"

namespace rigid::common {

struct ReplayReport {
  std::string journal;
  std::string scene;             // the scene file, or "JOURNAL (its copy of the scene)"
  std::string software_version;  // that wrote the journal
  std::string integrator;
  double rate_hz = 0.0;
  std::int64_t ticks = 0;  // stepped, over all resets
  std::int64_t wrenches = 0;
  std::int64_t controls = 0;
  std::int64_t resets = 0;
  std::int64_t edits = 0;
  std::int64_t hashes_compared = 0;
  std::int64_t contact_hashes_compared = 0;  // ticks with contact events, each verified
  std::int64_t contact_events = 0;           // in those ticks
  std::int64_t last_verified_tick = -1;      // of the last state found identical
  bool closed_cleanly = false;               // the journal ends with its LogEnd record
  std::string damage;                        // the journal's damaged tail, if any
  std::string csv;
  std::int64_t csv_rows = 0;
  std::vector<std::string> warnings;

  struct Divergence {
    std::int64_t tick = 0;
    std::uint64_t journaled = 0;
    std::uint64_t replayed = 0;
    std::string what;  // a hash mismatch, or a command the replay could not apply as live
  };
  std::optional<Divergence> divergence;
  struct Gap {
    std::int64_t tick = 0;
    std::int64_t dropped = 0;
  };
  std::optional<Gap> gap;  // entries rigidd lost: not verifiable from here on

  // 0 reproduced, 3 diverged, 4 stopped at a gap.
  int exit_status() const { return divergence ? 3 : gap ? 4 : 0; }
};

// Called with each replayed state whose hash matched the journal's, in journal order, as soon as it
// is verified: the same StateFrame rigidd published at that tick (tick, sim_time = tick x
// (1 / rate_hz) as rigidd computes it, every body), but for stamp_ns, which is 0 (rigidd's wall
// clock at publish is not journaled). rigidd hashes every distinct state it publishes (each
// publish_every-th tick, the tick after a command, the last of a step request, tick 0 after a
// reset; a paused rigidd's republishing of one tick once), so the sink sees exactly those, however
// many its buses then delivered. A state after a divergence or a gap is never passed. The frame is
// valid during the call only.
using StateSink = std::function<void(const rigid::StateFrame&)>;

// Called with each tick's contact events once their hash matched the journal's, in journal order:
// the ContactEvents message rigidd published for that tick (tick, sim_time, every event), but for
// stamp_ns and dropped, which are 0 (neither is journaled). A journal records a hash for every tick
// with events, and the replay checks both ways: a tick whose events the journal has and the replay
// lacks, or the other way round, is a divergence. Valid during the call only.
using ContactSink = std::function<void(const rigid::ContactEvents&)>;

struct ReplayOptions {
  std::string journal;             // rigidd --journal's file
  std::string scene;               // the scene it ran; empty: the journal's copy of it
  std::optional<std::string> csv;  // write the replayed states to this file (state CSV)
  // Write the replayed contact events to this file (contact CSV, common/contact_csv.hpp).
  std::optional<std::string> contacts_csv;
};

// The scene given is not the one the journal was recorded with, or none was given and the journal
// holds no copy (rigid-sim: a usage error, exit 2).
class SceneMismatch : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Runs the replay of options.journal. Throws SceneMismatch, scene::SceneError for a bad scene, and
// std::runtime_error for a journal that cannot be read or a CSV that cannot be written (exit 1).
// What `on_state` throws ends the replay and propagates.
ReplayReport replay(const ReplayOptions& options, const StateSink& on_state = {},
                    const ContactSink& on_contacts = {});

void print_replay(std::ostream& out, const ReplayReport& report);

}  // namespace rigid::common
