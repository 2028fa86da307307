// A writer of MCAP files (https://mcap.dev/spec, major version 0): the container Foxglove and
// other robotics tools open. Written for rigid-record export --mcap from the specification alone.
//
// What it writes (spec, "File Structure"):
//
//   Magic Header
//   data section:     Schema* Channel* then Chunk (MessageIndex per channel)*, DataEnd
//   summary section:  Schema* Channel* ChunkIndex* Statistics  (grouped by opcode, as required)
//   summary offsets:  one SummaryOffset per group
//   Footer Magic
//
// Messages go into chunks of about `chunk_bytes` (zstd-compressed unless told not to: MCAP's
// "zstd" compression, which Foxglove, the mcap CLI and the MCAP libraries read; a chunk that would
// not shrink is written uncompressed, compression ""), each followed by one MessageIndex
// per channel it holds, and every chunk has a ChunkIndex in the summary: so a reader opens a large
// file by reading its end (footer, summary offsets, chunk indexes) and seeks to the chunks it
// needs, instead of scanning it. Schemas and channels are written in the data section before the
// first chunk and repeated in the summary ("A Schema and Channel record MUST exist in the summary
// section for all messages in chunks that are indexed by Chunk Index records").
//
// Checksums are MCAP's CRC-32: the zlib/IEEE 802.3 polynomial (reflected 0xEDB88320, initial and
// final XOR 0xFFFFFFFF), not the CRC-32C of rigid's own log framing. Every byte is hashed once: a
// chunk's records are hashed for the chunk's uncompressed_crc, and that value is folded into the
// data-section CRC with crc32_combine instead of hashing the bytes again.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace rigid::record {

// CRC-32 (IEEE) of `bytes` continued from `crc` (0 to start): crc32(crc32(0, a), b) = crc32(0, ab).
std::uint32_t crc32(std::uint32_t crc, std::span<const std::uint8_t> bytes);
std::uint32_t crc32(std::uint32_t crc, std::string_view bytes);
// The CRC of A followed by B from crc(A), crc(B) and B's length, without B's bytes.
std::uint32_t crc32_combine(std::uint32_t crc_a, std::uint32_t crc_b, std::uint64_t length_b);

class McapWriter {
 public:
  // Where the file's bytes go, in order (e.g. an AtomicFile's write).
  using Sink = std::function<void(std::string_view)>;
  using Metadata = std::vector<std::pair<std::string, std::string>>;

  // Writes the magic and the Header record (profile: "" for none; library: who wrote the file).
  // `zstd_level` 0: chunks uncompressed.
  McapWriter(Sink sink, std::string_view profile, std::string_view library,
             std::size_t chunk_bytes = 4u << 20, int zstd_level = 3);
  ~McapWriter();
  McapWriter(const McapWriter&) = delete;
  McapWriter& operator=(const McapWriter&) = delete;

  // Schemas and channels must all be added before the first message (they are written once, in
  // the data section ahead of the chunks). Ids start at 1 (schema id 0 means "no schema").
  std::uint16_t add_schema(std::string_view name, std::string_view encoding, std::string_view data);
  std::uint16_t add_channel(std::uint16_t schema_id, std::string_view topic,
                            std::string_view message_encoding, const Metadata& metadata = {});

  // Times are nanoseconds since the Unix epoch. The message's bytes are copied.
  void write(std::uint16_t channel_id, std::uint32_t sequence, std::uint64_t log_time,
             std::uint64_t publish_time, std::string_view data);
  // A message whose bytes `encode` appends to the string it is given (no intermediate copy).
  void write_with(std::uint16_t channel_id, std::uint32_t sequence, std::uint64_t log_time,
                  std::uint64_t publish_time, const std::function<void(std::string&)>& encode);

  // Writes the last chunk, DataEnd, the summary, the summary offsets, the footer and the magic.
  void finish();

  std::uint64_t messages() const { return message_count_; }
  std::uint64_t bytes() const { return offset_; }

 private:
  struct ChunkIndex {
    std::uint64_t start_time = 0, end_time = 0, offset = 0, length = 0;
    std::map<std::uint16_t, std::uint64_t> index_offsets;
    std::uint64_t index_length = 0, uncompressed_size = 0, compressed_size = 0;
    bool zstd = false;
  };
  struct FreeCctx {
    void operator()(void* c) const;
  };
  void begin_message(std::uint16_t channel_id, std::uint64_t log_time);
  void end_message(std::size_t record_start);
  void emit(std::string_view bytes, std::uint32_t crc_of_bytes);
  void emit(std::string_view bytes);
  void flush_chunk();
  void write_definitions();

  Sink sink_;
  std::size_t chunk_bytes_;
  std::unique_ptr<void, FreeCctx> cctx_;  // null: no compression
  std::string compressed_;
  std::uint64_t offset_ = 0;    // bytes handed to the sink
  std::uint32_t data_crc_ = 0;  // of every byte so far (the data section's, until DataEnd)
  std::string schemas_;         // the Schema records, for the data section and the summary
  std::string channels_;        // the Channel records, likewise
  std::uint16_t schema_count_ = 0;
  std::uint16_t channel_count_ = 0;
  bool definitions_written_ = false;
  bool finished_ = false;

  // The open chunk: its records, and per channel the (log_time, offset) of its messages.
  std::string chunk_;
  std::map<std::uint16_t, std::vector<std::pair<std::uint64_t, std::uint64_t>>> chunk_index_;
  std::uint64_t chunk_start_ = 0, chunk_end_ = 0;
  bool chunk_has_messages_ = false;

  std::vector<ChunkIndex> chunk_indexes_;
  std::map<std::uint16_t, std::uint64_t> channel_counts_;
  std::uint64_t message_count_ = 0;
  std::uint64_t start_time_ = 0, end_time_ = 0;
  std::string scratch_;
};

}  // namespace rigid::record
