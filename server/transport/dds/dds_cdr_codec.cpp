#include "transport/dds/dds_cdr_codec.hpp"

#include <dds/dds.h>
#include <dds/ddsi/ddsi_cdrstream.h>

#include <limits>
#include <vector>

#include "transport/dds/dds_convert.hpp"

namespace rigid::transport::dds {
namespace {

// One message type's scratch: an output stream grown once and reused, and a sample whose
// sequences Cyclone reallocates only when a larger message arrives.
template <class Plain>
class Slot {
 public:
  using Dds = typename DdsTypeOf<Plain>::type;

  Slot() : ops_(DdsTypeOf<Plain>::descriptor->m_ops) {
    xcdr_version_ = dds_stream_minimum_xcdr_version(ops_);
    dds_ostream_init(&out_, 0, xcdr_version_);
  }
  ~Slot() {
    dds_ostream_fini(&out_);
    dds_stream_free_sample(&incoming_, ops_);
  }
  Slot(const Slot&) = delete;
  Slot& operator=(const Slot&) = delete;

  std::span<const std::uint8_t> encode(const Plain& message) {
    Dds outgoing{};
    if (!borrow(message, scratch_, outgoing)) return {};
    out_.m_index = 0;
    dds_stream_write(&out_, reinterpret_cast<const char*>(&outgoing), ops_);
    return {out_.m_buffer, out_.m_index};
  }

  DecodeStatus decode(std::span<const std::uint8_t> bytes, Plain& out) {
    if (bytes.size() > std::numeric_limits<std::uint32_t>::max()) return DecodeStatus::kMalformed;
    // No rigid message is empty; and an empty copy's data() is null, which Cyclone's stream
    // functions must not be given (declared nonnull: undefined behaviour, found by fuzzing).
    if (bytes.empty()) return DecodeStatus::kTruncated;
    const auto size = static_cast<std::uint32_t>(bytes.size());
    // Normalizing checks every length and may swap bytes in place, so it works on a copy.
    normalized_.assign(bytes.begin(), bytes.end());
    std::uint32_t end = 0;
    if (dds_stream_normalize_data(reinterpret_cast<char*>(normalized_.data()), &end, size, false,
                                  xcdr_version_, ops_) == nullptr) {
      return DecodeStatus::kMalformed;
    }
    dds_istream_t in;
    dds_istream_init(&in, size, normalized_.data(), xcdr_version_);
    dds_stream_read(&in, reinterpret_cast<char*>(&incoming_), ops_);
    dds_istream_fini(&in);
    return copy_from(incoming_, out);
  }

 private:
  const std::uint32_t* ops_;
  std::uint32_t xcdr_version_ = 0;
  dds_ostream_t out_{};
  BorrowScratch scratch_;
  std::vector<std::uint8_t> normalized_;
  Dds incoming_{};
};

}  // namespace

struct CdrCodec::Buffers {
  Slot<StateFrame> state;
  Slot<WrenchCommand> wrench;
  Slot<ControlCommand> control;
  Slot<ControlReply> reply;
  Slot<StatsReport> stats;
  Slot<SceneDescription> scene;
  Slot<AcceptedCommand> accepted;
};

CdrCodec::CdrCodec() : buffers_(std::make_unique<Buffers>()) {}
CdrCodec::~CdrCodec() = default;

std::span<const std::uint8_t> CdrCodec::encode(const StateFrame& m) {
  return buffers_->state.encode(m);
}
std::span<const std::uint8_t> CdrCodec::encode(const WrenchCommand& m) {
  return buffers_->wrench.encode(m);
}
std::span<const std::uint8_t> CdrCodec::encode(const ControlCommand& m) {
  return buffers_->control.encode(m);
}
std::span<const std::uint8_t> CdrCodec::encode(const ControlReply& m) {
  return buffers_->reply.encode(m);
}
std::span<const std::uint8_t> CdrCodec::encode(const StatsReport& m) {
  return buffers_->stats.encode(m);
}
std::span<const std::uint8_t> CdrCodec::encode(const SceneDescription& m) {
  return buffers_->scene.encode(m);
}
std::span<const std::uint8_t> CdrCodec::encode(const AcceptedCommand& m) {
  return buffers_->accepted.encode(m);
}

DecodeStatus CdrCodec::decode(std::span<const std::uint8_t> b, StateFrame& out) {
  return buffers_->state.decode(b, out);
}
DecodeStatus CdrCodec::decode(std::span<const std::uint8_t> b, WrenchCommand& out) {
  return buffers_->wrench.decode(b, out);
}
DecodeStatus CdrCodec::decode(std::span<const std::uint8_t> b, ControlCommand& out) {
  return buffers_->control.decode(b, out);
}
DecodeStatus CdrCodec::decode(std::span<const std::uint8_t> b, ControlReply& out) {
  return buffers_->reply.decode(b, out);
}
DecodeStatus CdrCodec::decode(std::span<const std::uint8_t> b, StatsReport& out) {
  return buffers_->stats.decode(b, out);
}
DecodeStatus CdrCodec::decode(std::span<const std::uint8_t> b, SceneDescription& out) {
  return buffers_->scene.decode(b, out);
}
DecodeStatus CdrCodec::decode(std::span<const std::uint8_t> b, AcceptedCommand& out) {
  return buffers_->accepted.decode(b, out);
}

}  // namespace rigid::transport::dds
