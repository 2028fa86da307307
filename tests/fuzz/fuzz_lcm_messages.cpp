// libFuzzer target: bytes arriving on LCM. Each input is decoded as every rigid message type with
// lcm::Codec (our layout check, then lcm-gen's generated decoder, then the conversion), as the LCM
// transport does for the channel a payload came on; wrenches and controls that decode then go
// through the server's validation (loop/command_validation.hpp). Beyond sanitizer findings it
// checks the promises of codec_round_trip.hpp and command_contract.hpp, and that lcm-gen's own
// decoder agrees with our layout of Control (whose fixed size makes the generated decoder safe to
// run on any bytes).
#include <climits>
#include <cstddef>
#include <cstdint>
#include <span>

#include "codec_round_trip.hpp"
#include "command_contract.hpp"
#include "rigid_lcm/Control.hpp"
#include "transport/lcm/lcm_codec.hpp"

namespace {

using namespace rigid;

struct Fixture {
  transport::lcm::Codec codec;
  fuzz::CommandContract contract;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static Fixture f;
  const std::span<const std::uint8_t> bytes(data, size);

  rigid::WrenchCommand wrench;
  if (fuzz::decode_checked(f.codec, bytes, wrench)) f.contract.check(wrench);

  rigid::ControlCommand control;
  const bool control_decoded = fuzz::decode_checked(f.codec, bytes, control);
  if (control_decoded) f.contract.check(control);
  if (size <= INT_MAX) {
    rigid_lcm::Control generated;
    const int n = static_cast<int>(size);
    fuzz::require((generated.decode(data, 0, n) == n) == control_decoded,
                  "lcm-gen's decoder and our layout check agree on Control");
  }

  rigid::EditCommand edit;
  if (fuzz::decode_checked(f.codec, bytes, edit)) f.contract.check(edit);

  // The types clients receive (rigidctl, rigid-record, rigid-view, controllers).
  rigid::StateFrame state;
  fuzz::decode_checked(f.codec, bytes, state);
  rigid::ControlReply reply;
  fuzz::decode_checked(f.codec, bytes, reply);
  rigid::StatsReport stats;
  fuzz::decode_checked(f.codec, bytes, stats);
  rigid::SceneDescription scene;
  fuzz::decode_checked(f.codec, bytes, scene);
  rigid::AcceptedCommand accepted;
  fuzz::decode_checked(f.codec, bytes, accepted);
  rigid::ContactEvents contacts;
  if (fuzz::decode_checked(f.codec, bytes, contacts)) {
    fuzz::require(contacts.event_count() <= rigid::kMaxContactEvents,
                  "a decoded ContactEvents holds at most kMaxContactEvents events");
  }
  return 0;
}
