// libFuzzer target: the server's command validation (loop/command_validation.hpp) on wrenches,
// controls and edits whose every field the input sets through FuzzedDataProvider, with numbers
// drawn mostly from the edges (zeros, infinities, NaN, the largest and smallest doubles, the limits
// and just past them). The bus fuzzers reach the validator through encoded messages, where a
// byte-wise mutation seldom makes such numbers in several fields at once. Checks
// command_contract.hpp.
#include <fuzzer/FuzzedDataProvider.h>

#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "command_contract.hpp"

namespace {

using namespace rigid;
using Limits = std::numeric_limits<double>;

double pick_double(FuzzedDataProvider& in) {
  const scene::Limits l = fuzz::CommandContract::limits();
  const double kEdges[] = {0.0,
                           -0.0,
                           1.0,
                           -1.0,
                           0.5,
                           Limits::infinity(),
                           -Limits::infinity(),
                           Limits::quiet_NaN(),
                           Limits::max(),
                           -Limits::max(),
                           1e308,
                           -1e308,
                           1e154,
                           -1e154,
                           Limits::min(),
                           Limits::denorm_min(),
                           l.max_force,
                           std::nextafter(l.max_force, Limits::infinity()),
                           l.max_torque,
                           std::nextafter(l.max_torque, Limits::infinity()),
                           l.max_ttl,
                           std::nextafter(l.max_ttl, Limits::infinity()),
                           loop::CommandValidator::kMaxRtf,
                           std::nextafter(loop::CommandValidator::kMaxRtf, 2e3)};
  switch (in.ConsumeIntegralInRange(0, 3)) {
    case 0:
    case 1:
      return in.PickValueInArray(kEdges);
    case 2:
      return in.ConsumeFloatingPoint<double>();
    default:
      return std::bit_cast<double>(in.ConsumeIntegral<std::uint64_t>());
  }
}

rigid::Vec3 pick_vec3(FuzzedDataProvider& in) {
  return {pick_double(in), pick_double(in), pick_double(in)};
}

// A frame or command number: mostly a known one, sometimes anything.
template <class Enum>
Enum pick_enum(FuzzedDataProvider& in, std::int32_t last_known) {
  return static_cast<Enum>(in.ConsumeBool() ? in.ConsumeIntegralInRange<std::int32_t>(0, last_known)
                                            : in.ConsumeIntegral<std::int32_t>());
}

rigid::WrenchCommand make_wrench(FuzzedDataProvider& in) {
  static const std::vector<std::string> kNames = fuzz::CommandContract::body_names();
  rigid::WrenchCommand w;
  w.source = in.ConsumeIntegral<std::int64_t>();
  w.seq = in.ConsumeIntegral<std::int64_t>();
  w.key = in.ConsumeIntegral<std::int32_t>();
  switch (in.ConsumeIntegralInRange(0, 2)) {
    case 0:  // by id, valid or not
      w.body_id = in.ConsumeIntegralInRange<std::int32_t>(-1, static_cast<int>(kNames.size()));
      break;
    case 1:  // by a name of the scene
      w.body_id = -1 - in.ConsumeIntegralInRange(0, 3);
      w.body_name = kNames[in.ConsumeIntegralInRange<std::size_t>(0, kNames.size() - 1)];
      break;
    default:  // by any name, any id
      w.body_id = in.ConsumeIntegral<std::int32_t>();
      w.body_name = in.ConsumeRandomLengthString(80);
      break;
  }
  w.force = pick_vec3(in);
  w.point = pick_vec3(in);
  w.force_frame = pick_enum<rigid::Frame>(in, 1);
  w.torque = pick_vec3(in);
  w.torque_frame = pick_enum<rigid::Frame>(in, 1);
  w.ttl = pick_double(in);
  w.stamp_ns = in.ConsumeIntegral<std::int64_t>();
  return w;
}

rigid::ControlCommand make_control(FuzzedDataProvider& in) {
  constexpr std::int64_t kMax = loop::CommandValidator::kMaxSteps;
  const std::int64_t kSteps[] = {0,
                                 1,
                                 2,
                                 kMax,
                                 kMax + 1,
                                 -1,
                                 std::numeric_limits<std::int64_t>::min(),
                                 std::numeric_limits<std::int64_t>::max()};
  rigid::ControlCommand c;
  c.source = in.ConsumeIntegral<std::int64_t>();
  c.seq = in.ConsumeIntegral<std::int64_t>();
  c.command = pick_enum<rigid::ControlKind>(in, 6);
  c.steps = in.ConsumeBool() ? in.PickValueInArray(kSteps) : in.ConsumeIntegral<std::int64_t>();
  c.rtf = pick_double(in);
  return c;
}

rigid::EditCommand make_edit(FuzzedDataProvider& in) {
  rigid::EditCommand e;
  e.source = in.ConsumeIntegral<std::int64_t>();
  e.seq = in.ConsumeIntegral<std::int64_t>();
  e.kind = pick_enum<rigid::EditKind>(in, 3);
  e.body_id = in.ConsumeBool() ? in.ConsumeIntegralInRange<std::int32_t>(-2, 5)
                               : in.ConsumeIntegral<std::int32_t>();
  static const std::vector<std::string> kNames = fuzz::CommandContract::body_names();
  if (e.body_id < 0) {
    e.body_name = in.ConsumeBool()
                      ? kNames[in.ConsumeIntegralInRange<std::size_t>(0, kNames.size() - 1)]
                      : in.ConsumeRandomLengthString(140);
  }
  e.set = in.ConsumeBool() ? in.ConsumeIntegralInRange<std::int32_t>(0, 16)
                           : in.ConsumeIntegral<std::int32_t>();
  e.position = pick_vec3(in);
  if (in.ConsumeBool()) {
    // Near unit length, on both sides of the tolerance.
    const double scale = 1.0 + (in.ConsumeProbability<double>() - 0.5) * 4e-3;
    e.orientation = {0.5 * scale, 0.5 * scale, -0.5 * scale, 0.5 * scale};
  } else {
    e.orientation = {pick_double(in), pick_double(in), pick_double(in), pick_double(in)};
  }
  e.linear_velocity = pick_vec3(in);
  e.velocity_frame = pick_enum<rigid::Frame>(in, 1);
  e.angular_velocity = pick_vec3(in);
  e.angular_velocity_frame = pick_enum<rigid::Frame>(in, 1);
  e.stamp_ns = in.ConsumeIntegral<std::int64_t>();
  return e;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const fuzz::CommandContract contract;
  FuzzedDataProvider in(data, size);
  // Several commands per input, of either kind.
  while (in.remaining_bytes() > 0) {
    switch (in.ConsumeIntegralInRange(0, 2)) {
      case 0:
        contract.check(make_wrench(in));
        break;
      case 1:
        contract.check(make_control(in));
        break;
      default:
        contract.check(make_edit(in));
        break;
    }
  }
  return 0;
}
