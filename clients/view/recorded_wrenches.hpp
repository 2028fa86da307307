// rigid-view FILE: which of a recording's accepted wrenches act at each of its states, so that
// playback draws the arrows live mode draws (protocol.hpp wrenches_json).
//
// rigidd takes a wrench between ticks: accepted at tick k (AcceptedCommand::tick), it acts on the
// steps k -> k+1 ... k+n-1 -> k+n, n = ticks_to_live(ttl, dt) (server/common/wrench_table.hpp), so
// it is shown with the states its steps produced: k < tick <= k + n. A later wrench with the same
// (source, body, key) replaces it from its own tick k' (shown up to k'), and a reset at tick r
// clears it (shown up to r), as does a reset of its body alone (an edit), as rigidd's wrench
// table does.
//
// A recording holds two streams in one file: the states and the accepted commands, each in order,
// but not in order with each other (rigid-record writes each as it arrives). Ticks start again
// after a reset (or a restarted rigidd), so a wrench's tick means something only within its
// stretch: the states between two places where the recorded tick goes back (RecordedState::
// stretch). A wrench's stretch is the one the states had reached where it was recorded, unless a
// reset (or a new scene: rigidd restarted) came before it in the command stream whose states have
// not yet arrived (then the next), or the states have gone back without the command stream having
// said why yet (a reset's command written after its first state, or a restart): then the
// stretch, of the last two, whose last recorded tick is nearest to the wrench's.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <tuple>
#include <vector>

#include "rigid/messages.hpp"

namespace rigid::view {

struct RecordedWrench {
  AcceptedCommand command;    // kind kWrench
  std::uint32_t stretch = 0;  // RecordedState::stretch of the states it acts on
  std::int64_t ticks = 0;     // ticks_to_live(ttl, dt); < 0 until finish() knows dt
  // Acts on the states of its stretch with command.tick < tick <= until (after finish(): at most
  // command.tick + ticks; before, the tick a newer wrench or a reset cut it at, if any).
  std::int64_t until = 0;
};

class RecordedWrenches {
 public:
  // Fed in file order: a state's tick (or a journal's state hash: the states rigidd published),
  // a scene that differs from the one before, an accepted command (at dt s a tick; 0: not known
  // yet, an lcm-logger log's commands before its first SceneInfo).
  void state(std::int64_t tick);
  void scene_changed();
  void command(const AcceptedCommand& a, double dt);
  // After the last of them: the ticks of the wrenches whose dt was not known (the first scene's,
  // first_dt), and the wrenches ordered for acting().
  void finish(double first_dt);

  // The wrenches acting on the state (stretch, tick), the newest (highest tick) last, at most
  // `max` of them (the newest), as indices into all().
  std::vector<std::size_t> acting(std::uint32_t stretch, std::int64_t tick, std::size_t max) const;
  const std::vector<RecordedWrench>& all() const { return wrenches_; }

 private:
  std::uint32_t stretch_of(std::int64_t tick) const;

  std::vector<RecordedWrench> wrenches_;  // by (stretch, tick): the command stream's order
  std::int64_t longest_ = 0;              // of until - command.tick: how far back acting() looks
  // The states' side: the stretch reached, and the last tick recorded in it and the one before.
  std::uint32_t states_stretch_ = 0;
  bool any_state_ = false;
  std::int64_t last_tick_ = 0, previous_last_tick_ = 0;
  std::uint32_t states_in_stretch_ = 0;
  // Resets (and scene changes) read in the command stream whose states have not arrived yet, and
  // places where the states went back before the command stream said why.
  std::uint32_t pending_ = 0, owed_ = 0;
  // The newest wrench per (stretch, source, body, key): the one a newer wrench or a reset cuts.
  std::map<std::tuple<std::uint32_t, std::int64_t, std::int32_t, std::int32_t>, std::size_t> open_;
};

}  // namespace rigid::view
