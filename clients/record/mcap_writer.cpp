#include "record/mcap_writer.hpp"

#include <zstd.h>

#include <array>
#include <bit>
#include <cstring>
#include <stdexcept>

namespace rigid::record {
namespace {

static_assert(
    std::endian::native == std::endian::little,
    "MCAP integers are little-endian (spec, Serialization); this writer copies them as is");

// The reflected IEEE 802.3 polynomial: MCAP's CRC32 is zlib's (spec, Chunk and Footer records).
constexpr std::uint32_t kPoly = 0xEDB88320u;

// Slicing-by-8 tables: table[k][b] is the CRC register after byte b followed by k zero bytes, so
// eight bytes are folded per step with eight independent lookups.
constexpr std::array<std::array<std::uint32_t, 256>, 8> make_tables() {
  std::array<std::array<std::uint32_t, 256>, 8> t{};
  for (std::uint32_t i = 0; i < 256; ++i) {
    std::uint32_t c = i;
    for (int k = 0; k < 8; ++k)
      c = (c & 1u) ? (c >> 1) ^ kPoly : c >> 1;
    t[0][i] = c;
  }
  for (std::size_t k = 1; k < 8; ++k) {
    for (std::size_t i = 0; i < 256; ++i)
      t[k][i] = (t[k - 1][i] >> 8) ^ t[0][t[k - 1][i] & 0xFFu];
  }
  return t;
}
constexpr auto kTables = make_tables();

// a(x) b(x) mod P(x), both in the reflected representation (bit 31 is the coefficient of x^0).
std::uint32_t multiply_mod_p(std::uint32_t a, std::uint32_t b) {
  std::uint32_t product = 0;
  for (std::uint32_t m = 1u << 31; m != 0; m >>= 1) {
    if (a & m) product ^= b;
    b = (b & 1u) ? (b >> 1) ^ kPoly : b >> 1;  // b *= x
  }
  return product;
}

// x^(2^k) mod P for k = 0..63, by repeated squaring.
std::array<std::uint32_t, 64> make_powers() {
  std::array<std::uint32_t, 64> p{};
  p[0] = 1u << 30;  // x^1
  for (std::size_t k = 1; k < p.size(); ++k)
    p[k] = multiply_mod_p(p[k - 1], p[k - 1]);
  return p;
}

void put_u8(std::string& s, std::uint8_t v) {
  s.push_back(static_cast<char>(v));
}
template <class T>
void put_int(std::string& s, T v) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &v, sizeof(T));
  s.append(bytes, sizeof(T));
}
void put_u16(std::string& s, std::uint16_t v) {
  put_int(s, v);
}
void put_u32(std::string& s, std::uint32_t v) {
  put_int(s, v);
}
void put_u64(std::string& s, std::uint64_t v) {
  put_int(s, v);
}
void put_string(std::string& s, std::string_view v) {
  put_u32(s, static_cast<std::uint32_t>(v.size()));
  s.append(v);
}
void patch_u64(std::string& s, std::size_t at, std::uint64_t v) {
  std::memcpy(s.data() + at, &v, sizeof v);
}

// Record opcodes (spec, "Records").
enum Op : std::uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kMessageIndex = 0x07,
  kChunkIndex = 0x08,
  kStatistics = 0x0B,
  kSummaryOffset = 0x0E,
  kDataEnd = 0x0F,
};

constexpr std::string_view kMagic{"\x89MCAP0\r\n", 8};

// Starts a record: opcode and a length patched by end_record.
std::size_t begin_record(std::string& s, Op op) {
  put_u8(s, op);
  const std::size_t at = s.size();
  put_u64(s, 0);
  return at;
}
void end_record(std::string& s, std::size_t length_at) {
  patch_u64(s, length_at, s.size() - length_at - 8);
}

}  // namespace

std::uint32_t crc32(std::uint32_t crc, std::span<const std::uint8_t> bytes) {
  std::uint32_t c = ~crc;
  const std::uint8_t* p = bytes.data();
  std::size_t n = bytes.size();
  for (; n >= 8; p += 8, n -= 8) {
    std::uint32_t lo;
    std::uint32_t hi;
    std::memcpy(&lo, p, 4);
    std::memcpy(&hi, p + 4, 4);
    lo ^= c;
    c = kTables[7][lo & 0xFFu] ^ kTables[6][(lo >> 8) & 0xFFu] ^ kTables[5][(lo >> 16) & 0xFFu] ^
        kTables[4][lo >> 24] ^ kTables[3][hi & 0xFFu] ^ kTables[2][(hi >> 8) & 0xFFu] ^
        kTables[1][(hi >> 16) & 0xFFu] ^ kTables[0][hi >> 24];
  }
  for (; n > 0; ++p, --n)
    c = (c >> 8) ^ kTables[0][(c ^ *p) & 0xFFu];
  return ~c;
}

std::uint32_t crc32(std::uint32_t crc, std::string_view bytes) {
  return crc32(crc, std::span(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()));
}

// crc(AB) = crc(A) x^(8 |B|) + crc(B) mod P: the pre- and post-inversions of the two parts cancel
// (the same identity as zlib's crc32_combine; derived here from the CRC's linearity).
std::uint32_t crc32_combine(std::uint32_t crc_a, std::uint32_t crc_b, std::uint64_t length_b) {
  static const std::array<std::uint32_t, 64> powers = make_powers();
  std::uint32_t shift = 1u << 31;  // x^0
  std::uint64_t bits = length_b;
  for (std::size_t k = 3; bits != 0 && k < powers.size(); ++k, bits >>= 1) {  // 2^3 bits a byte
    if (bits & 1u) shift = multiply_mod_p(powers[k], shift);
  }
  return multiply_mod_p(shift, crc_a) ^ crc_b;
}

void McapWriter::FreeCctx::operator()(void* c) const {
  ZSTD_freeCCtx(static_cast<ZSTD_CCtx*>(c));
}

McapWriter::~McapWriter() = default;

McapWriter::McapWriter(Sink sink, std::string_view profile, std::string_view library,
                       std::size_t chunk_bytes, int zstd_level)
    : sink_(std::move(sink)), chunk_bytes_(chunk_bytes) {
  if (zstd_level > 0) {
    cctx_.reset(ZSTD_createCCtx());
    if (!cctx_ || ZSTD_isError(ZSTD_CCtx_setParameter(static_cast<ZSTD_CCtx*>(cctx_.get()),
                                                      ZSTD_c_compressionLevel, zstd_level))) {
      throw std::runtime_error("MCAP: cannot set up zstd compression");
    }
  }
  std::string s(kMagic);
  const std::size_t at = begin_record(s, kHeader);
  put_string(s, profile);
  put_string(s, library);
  end_record(s, at);
  emit(s);
  chunk_.reserve(chunk_bytes_ + (1u << 20));
}

std::uint16_t McapWriter::add_schema(std::string_view name, std::string_view encoding,
                                     std::string_view data) {
  if (definitions_written_) throw std::logic_error("McapWriter: a schema after the first message");
  const std::uint16_t id = ++schema_count_;
  const std::size_t at = begin_record(schemas_, kSchema);
  put_u16(schemas_, id);
  put_string(schemas_, name);
  put_string(schemas_, encoding);
  put_string(schemas_, data);  // uint32 length-prefixed bytes
  end_record(schemas_, at);
  return id;
}

std::uint16_t McapWriter::add_channel(std::uint16_t schema_id, std::string_view topic,
                                      std::string_view message_encoding, const Metadata& metadata) {
  if (definitions_written_) throw std::logic_error("McapWriter: a channel after the first message");
  const std::uint16_t id = ++channel_count_;
  const std::size_t at = begin_record(channels_, kChannel);
  put_u16(channels_, id);
  put_u16(channels_, schema_id);
  put_string(channels_, topic);
  put_string(channels_, message_encoding);
  std::string map;
  for (const auto& [key, value] : metadata) {
    put_string(map, key);
    put_string(map, value);
  }
  put_string(channels_, map);  // Map<string, string>: uint32 byte length, then key, value, ...
  end_record(channels_, at);
  return id;
}

void McapWriter::write_definitions() {
  emit(schemas_);
  emit(channels_);
  definitions_written_ = true;
}

void McapWriter::begin_message(std::uint16_t channel_id, std::uint64_t log_time) {
  if (finished_) throw std::logic_error("McapWriter: a message after finish()");
  if (!definitions_written_) write_definitions();
  chunk_index_[channel_id].emplace_back(log_time, chunk_.size());
  if (!chunk_has_messages_ || log_time < chunk_start_) chunk_start_ = log_time;
  if (!chunk_has_messages_ || log_time > chunk_end_) chunk_end_ = log_time;
  if (message_count_ == 0 || log_time < start_time_) start_time_ = log_time;
  if (message_count_ == 0 || log_time > end_time_) end_time_ = log_time;
  chunk_has_messages_ = true;
  ++message_count_;
  ++channel_counts_[channel_id];
}

void McapWriter::end_message(std::size_t record_start) {
  end_record(chunk_, record_start + 1);
  if (chunk_.size() >= chunk_bytes_) flush_chunk();
}

void McapWriter::write(std::uint16_t channel_id, std::uint32_t sequence, std::uint64_t log_time,
                       std::uint64_t publish_time, std::string_view data) {
  write_with(channel_id, sequence, log_time, publish_time,
             [data](std::string& s) { s.append(data); });
}

void McapWriter::write_with(std::uint16_t channel_id, std::uint32_t sequence,
                            std::uint64_t log_time, std::uint64_t publish_time,
                            const std::function<void(std::string&)>& encode) {
  const std::size_t start = chunk_.size();
  begin_message(channel_id, log_time);
  begin_record(chunk_, kMessage);
  put_u16(chunk_, channel_id);
  put_u32(chunk_, sequence);
  put_u64(chunk_, log_time);
  put_u64(chunk_, publish_time);
  encode(chunk_);
  end_message(start);
}

void McapWriter::emit(std::string_view bytes, std::uint32_t crc_of_bytes) {
  sink_(bytes);
  offset_ += bytes.size();
  data_crc_ = crc32_combine(data_crc_, crc_of_bytes, bytes.size());
}

void McapWriter::emit(std::string_view bytes) {
  emit(bytes, crc32(0, bytes));
}

void McapWriter::flush_chunk() {
  if (chunk_.empty()) return;
  const std::uint32_t records_crc = crc32(0, chunk_);
  ChunkIndex index;
  index.start_time = chunk_has_messages_ ? chunk_start_ : 0;
  index.end_time = chunk_has_messages_ ? chunk_end_ : 0;
  index.offset = offset_;
  index.uncompressed_size = chunk_.size();

  // The records zstd-compressed (one zstd frame), unless that would not make them smaller.
  if (cctx_) {
    compressed_.resize(ZSTD_compressBound(chunk_.size()));
    const std::size_t n = ZSTD_compress2(static_cast<ZSTD_CCtx*>(cctx_.get()), compressed_.data(),
                                         compressed_.size(), chunk_.data(), chunk_.size());
    index.zstd = !ZSTD_isError(n) && n < chunk_.size();
    if (index.zstd) compressed_.resize(n);
  }
  const std::string_view records = index.zstd ? std::string_view(compressed_) : chunk_;
  const std::string_view compression = index.zstd ? "zstd" : "";
  index.compressed_size = records.size();

  // Chunk (op 0x06): start and end log_time, uncompressed size and CRC (of the records before
  // compression), compression ("zstd" or "" for none), then the records as uint64
  // length-prefixed bytes.
  std::string head;
  put_u8(head, kChunk);
  put_u64(head, 8 + 8 + 8 + 4 + 4 + compression.size() + 8 + records.size());
  put_u64(head, index.start_time);
  put_u64(head, index.end_time);
  put_u64(head, chunk_.size());
  put_u32(head, records_crc);
  put_string(head, compression);
  put_u64(head, records.size());
  emit(head);
  if (index.zstd) {
    emit(records);
  } else {
    emit(records, records_crc);
  }
  index.length = head.size() + records.size();

  // One Message Index (op 0x07) per channel in the chunk: (log_time, offset in the records).
  std::string indexes;
  for (const auto& [channel, entries] : chunk_index_) {
    index.index_offsets[channel] = offset_ + indexes.size();
    const std::size_t at = begin_record(indexes, kMessageIndex);
    put_u16(indexes, channel);
    put_u32(indexes, static_cast<std::uint32_t>(entries.size() * 16));
    for (const auto& [time, at_offset] : entries) {
      put_u64(indexes, time);
      put_u64(indexes, at_offset);
    }
    end_record(indexes, at);
  }
  index.index_length = indexes.size();
  emit(indexes);
  chunk_indexes_.push_back(std::move(index));

  chunk_.clear();
  chunk_index_.clear();
  chunk_has_messages_ = false;
}

void McapWriter::finish() {
  if (finished_) return;
  flush_chunk();
  if (!definitions_written_) write_definitions();
  finished_ = true;

  // Data End (op 0x0F): the CRC of every byte from the start of the file up to this record.
  std::string end;
  const std::size_t end_at = begin_record(end, kDataEnd);
  put_u32(end, data_crc_);
  end_record(end, end_at);
  sink_(end);
  offset_ += end.size();

  // The summary, grouped by opcode; each group's place goes into a Summary Offset record.
  const std::uint64_t summary_start = offset_;
  std::string summary;
  std::string offsets;
  const auto group = [&](Op op, std::string_view records) {
    if (records.empty()) return;
    const std::size_t at = begin_record(offsets, kSummaryOffset);
    put_u8(offsets, op);
    put_u64(offsets, summary_start + summary.size());
    put_u64(offsets, records.size());
    end_record(offsets, at);
    summary.append(records);
  };
  group(kSchema, schemas_);
  group(kChannel, channels_);

  std::string chunk_indexes;
  for (const ChunkIndex& c : chunk_indexes_) {
    const std::size_t at = begin_record(chunk_indexes, kChunkIndex);
    put_u64(chunk_indexes, c.start_time);
    put_u64(chunk_indexes, c.end_time);
    put_u64(chunk_indexes, c.offset);
    put_u64(chunk_indexes, c.length);
    put_u32(chunk_indexes, static_cast<std::uint32_t>(c.index_offsets.size() * 10));
    for (const auto& [channel, offset] : c.index_offsets) {
      put_u16(chunk_indexes, channel);
      put_u64(chunk_indexes, offset);
    }
    put_u64(chunk_indexes, c.index_length);
    put_string(chunk_indexes, c.zstd ? "zstd" : "");
    put_u64(chunk_indexes, c.compressed_size);
    put_u64(chunk_indexes, c.uncompressed_size);
    end_record(chunk_indexes, at);
  }
  group(kChunkIndex, chunk_indexes);

  std::string stats;
  const std::size_t stats_at = begin_record(stats, kStatistics);
  put_u64(stats, message_count_);
  put_u16(stats, schema_count_);
  put_u32(stats, channel_count_);
  put_u32(stats, 0);  // attachments
  put_u32(stats, 0);  // metadata
  put_u32(stats, static_cast<std::uint32_t>(chunk_indexes_.size()));
  put_u64(stats, message_count_ ? start_time_ : 0);
  put_u64(stats, message_count_ ? end_time_ : 0);
  put_u32(stats, static_cast<std::uint32_t>(channel_counts_.size() * 10));
  for (const auto& [channel, count] : channel_counts_) {
    put_u16(stats, channel);
    put_u64(stats, count);
  }
  end_record(stats, stats_at);
  group(kStatistics, stats);

  const std::uint64_t offsets_start = summary_start + summary.size();
  summary.append(offsets);

  // Footer (op 0x02): its summary_crc covers the summary and summary offset sections and the
  // footer's own bytes up to and including summary_offset_start (so its length is written first).
  put_u8(summary, kFooter);
  put_u64(summary, 8 + 8 + 4);
  put_u64(summary, summary_start);
  put_u64(summary, offsets.empty() ? 0 : offsets_start);
  put_u32(summary, crc32(0, summary));
  summary.append(kMagic);
  sink_(summary);
  offset_ += summary.size();
}

}  // namespace rigid::record
