// CSV rows of body states.
#include "sim/state_csv.hpp"

#include <array>
#include <charconv>

namespace rigid::sim {
namespace {

// Same digits as printf("%.17g"), but independent of the C locale's decimal point.
void append_number(std::string& out, double x) {
  std::array<char, 32> buf{};
  const auto r =
      std::to_chars(buf.data(), buf.data() + buf.size(), x, std::chars_format::general, 17);
  out.append(buf.data(), r.ptr);
}

}  // namespace

void append_state_row(std::string& out, double t, std::string_view body,
                      const std::array<double, 13>& values) {
  append_number(out, t);
  out += ',';
  // Body names are restricted by the scene loader to characters that need no CSV quoting.
  out += body;
  for (double v : values) {
    out += ',';
    append_number(out, v);
  }
  out += '\n';
}

void append_state_rows(const physics::World& world, std::string& out) {
  const double t = world.time();
  for (int id = 0; id < world.body_count(); ++id) {
    const physics::BodyState s = world.state(id);
    append_state_row(
        out, t, world.body_spec(id).name,
        {s.p_WBo.x(), s.p_WBo.y(), s.p_WBo.z(), s.q_WB.w(), s.q_WB.x(), s.q_WB.y(), s.q_WB.z(),
         s.v_WBo.x(), s.v_WBo.y(), s.v_WBo.z(), s.w_WB.x(), s.w_WB.y(), s.w_WB.z()});
  }
}

}  // namespace rigid::sim
