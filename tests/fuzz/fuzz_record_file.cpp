// libFuzzer target: any bytes as a log file (recording or journal; format 1, or 2 with zstd
// chunks) read by common::RecordReader,
// as rigid-record info/export/play and rigid-sim --replay read them. The reader must refuse the
// file with a LogFileError or read records until the end or a damaged tail, never crash; its
// offsets must add up (every byte is either read or reported as damaged); and each record that
// parsed goes through record_checks.hpp. Checksums make most mutated frames damaged:
// fuzz_log_record covers what is inside a frame.
#include <cstddef>
#include <cstdint>
#include <optional>

#include "common/record_file.hpp"
#include "fuzz_require.hpp"
#include "memory_file.hpp"
#include "record_checks.hpp"

using rigid::fuzz::require;

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  rigid::fuzz::quiet_protobuf();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const rigid::fuzz::MemoryFile file(data, size);
  std::optional<rigid::common::RecordReader> reader;
  try {
    reader.emplace(file.path());
  } catch (const rigid::common::LogFileError&) {
    return 0;
  }
  require(size >= rigid::common::kLogPreambleBytes, "an accepted file holds its preamble");
  require(reader->size() == size && reader->offset() == rigid::common::kLogPreambleBytes,
          "the reader starts after the preamble");

  rigid::msgs::LogRecord record;
  std::uint64_t offset = reader->offset();
  std::int64_t records = 0;
  // A record frame moves the reader on; the records of a chunk leave it at the chunk's start until
  // the last, which moves it past the chunk.
  while (reader->next(record)) {
    require(reader->offset() == offset ||
                (reader->offset() >= offset + rigid::common::kFrameHeaderBytes &&
                 reader->offset() <= size),
            "each record leaves the reader where it was (in a chunk) or moves it on, within the "
            "file");
    offset = reader->offset();
    ++records;
    rigid::fuzz::check_record(record);
  }
  require(reader->chunk_record_bytes() <=
              static_cast<std::uint64_t>(reader->chunks()) * rigid::common::kMaxChunkBytes,
          "no chunk held more than a reader may hold");
  require(reader->records() == records, "the reader counts the records it returned");
  require(!reader->next(record), "the reader stays at the end");
  if (const auto& damage = reader->damage()) {
    require(damage->offset == offset && damage->offset + damage->bytes == size &&
                !damage->reason.empty(),
            "a damaged tail starts after the last record and runs to the end of the file");
  } else {
    require(offset == size, "without damage the reader reads the whole file");
  }
  return 0;
}
