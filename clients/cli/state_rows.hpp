// A received state as rigid-sim's CSV rows (util/state_csv.hpp: t,body,x,...,wz, 17 significant
// digits), one row per body, named from the scene. For rigidctl echo --csv and rigid-record export.
#pragma once

#include <string>
#include <unordered_map>

#include "rigid/messages.hpp"

namespace rigid::clients {

// Body names by id; ids the scene does not name are written as their number.
class BodyNames {
 public:
  BodyNames() = default;
  explicit BodyNames(const rigid::SceneDescription& scene);
  std::string name(std::int32_t id) const;
  bool empty() const { return names_.empty(); }

 private:
  std::unordered_map<std::int32_t, std::string> names_;
};

// One row per body of `frame` (t is its sim_time), or only the bodies with `only[i]` set when
// `only` is not empty (indexed like the frame's bodies).
void append_frame_rows(const rigid::StateFrame& frame, const BodyNames& names, std::string& out,
                       const std::vector<bool>& only = {});

}  // namespace rigid::clients
