// CSV rows of the world's body states.
#include "common/world_csv.hpp"

namespace rigid::common {

void append_state_rows(const physics::World& world, std::string& out) {
  const double t = world.time();
  for (int id = 0; id < world.body_count(); ++id) {
    const physics::BodyState s = world.state(id);
    util::append_state_row(
        out, t, world.body_name(id),
        {s.p_WBo.x(), s.p_WBo.y(), s.p_WBo.z(), s.q_WB.w(), s.q_WB.x(), s.q_WB.y(), s.q_WB.z(),
         s.v_WBo.x(), s.v_WBo.y(), s.v_WBo.z(), s.w_WB.x(), s.w_WB.y(), s.w_WB.z()});
  }
}

}  // namespace rigid::common
