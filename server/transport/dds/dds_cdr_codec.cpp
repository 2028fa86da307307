#include "transport/dds/dds_cdr_codec.hpp"

#include <dds/dds.h>
#include <dds/ddsi/ddsi_cdrstream.h>

#include <limits>
#include <tuple>
#include <vector>

#include "transport/codec_impl.hpp"
#include "transport/dds/dds_convert.hpp"

namespace rigid::transport::dds {

// One message type's scratch: an output stream grown once and reused, and a sample whose
// sequences Cyclone reallocates only when a larger message arrives.
template <class Plain>
class CdrSlot {
 public:
  using Dds = typename DdsTypeOf<Plain>::type;

  CdrSlot() : ops_(DdsTypeOf<Plain>::descriptor->m_ops) {
    xcdr_version_ = dds_stream_minimum_xcdr_version(ops_);
    dds_ostream_init(&out_, 0, xcdr_version_);
  }
  ~CdrSlot() {
    dds_ostream_fini(&out_);
    dds_stream_free_sample(&incoming_, ops_);
  }
  CdrSlot(const CdrSlot&) = delete;
  CdrSlot& operator=(const CdrSlot&) = delete;

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

}  // namespace rigid::transport::dds

namespace rigid::transport {

template <>
struct CodecBuffers<Bus::kDds> {
  template <class Plain>
  std::span<const std::uint8_t> encode(const Plain& message) {
    return std::get<dds::CdrSlot<Plain>>(slots).encode(message);
  }
  template <class Plain>
  DecodeStatus decode(std::span<const std::uint8_t> bytes, Plain& out) {
    return std::get<dds::CdrSlot<Plain>>(slots).decode(bytes, out);
  }

  std::tuple<dds::CdrSlot<StateFrame>, dds::CdrSlot<WrenchCommand>, dds::CdrSlot<ControlCommand>,
             dds::CdrSlot<ControlReply>, dds::CdrSlot<StatsReport>, dds::CdrSlot<SceneDescription>,
             dds::CdrSlot<AcceptedCommand>, dds::CdrSlot<ContactEvents>, dds::CdrSlot<EditCommand>>
      slots;
};

template class Codec<Bus::kDds>;

}  // namespace rigid::transport
