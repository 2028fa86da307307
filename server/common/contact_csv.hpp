// The CSV format of contact events: one row per event, named by the scene (its bodies and static
// parts), every number with 17 significant digits so that a double survives the round trip
// through text. rigid-sim --contacts-csv writes it (a run's events, or a journal's replayed).
//
//   tick,t,kind,body,part,px,py,pz,nx,ny,nz,jx,jy,jz
//
// tick: the tick whose steps the event happened in; t: its exact sim time (s); kind: impact,
// resting, sliding, rolling, separate; part: empty for a separate event (no one part); p: where,
// n: the part's unit normal there towards the body, j: the impulse on the body (N s; zero but for
// an impact), all in the world frame.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "rigid/messages.hpp"

namespace rigid::common {

inline constexpr std::string_view kContactCsvHeader =
    "tick,t,kind,body,part,px,py,pz,nx,ny,nz,jx,jy,jz\n";

// Body names by id and static part names by index; an id or index without a name is written as
// its number.
class ContactNames {
 public:
  ContactNames() = default;
  explicit ContactNames(const rigid::SceneDescription& scene);
  std::string body(std::int32_t id) const;
  std::string part(std::int32_t index) const;

 private:
  std::vector<std::string> bodies_;  // by id
  std::vector<std::string> parts_;
};

// One row per event of `events` (whose lengths must agree).
void append_contact_rows(const rigid::ContactEvents& events, const ContactNames& names,
                         std::string& out);

}  // namespace rigid::common
