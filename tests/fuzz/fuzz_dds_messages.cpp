// libFuzzer target: bytes arriving on Cyclone DDS. Each input is taken as a sample's CDR payload
// (XCDR1, native byte order, without the 4-byte encapsulation header) and decoded as every rigid
// message type with dds::CdrCodec: Cyclone's own validation of received data
// (dds_stream_normalize_data), its deserializer into idlc's C type (dds_stream_read, driven by the
// generated topic descriptor), then our conversion (dds_convert). Wrenches and controls that decode
// then go through the server's validation (loop/command_validation.hpp). Beyond sanitizer
// findings it checks the promises of codec_round_trip.hpp and command_contract.hpp.
#include <cstddef>
#include <cstdint>
#include <span>

#include "codec_round_trip.hpp"
#include "command_contract.hpp"
#include "transport/dds/dds_cdr_codec.hpp"

namespace {

using namespace rigid;

struct Fixture {
  transport::dds::CdrCodec codec;
  fuzz::CommandContract contract;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static Fixture f;
  const std::span<const std::uint8_t> bytes(data, size);

  rigid::WrenchCommand wrench;
  if (fuzz::decode_checked(f.codec, bytes, wrench)) f.contract.check(wrench);
  rigid::ControlCommand control;
  if (fuzz::decode_checked(f.codec, bytes, control)) f.contract.check(control);

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
