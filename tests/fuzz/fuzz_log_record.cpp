// libFuzzer target: any bytes as the payload of one frame, i.e. a serialized rigid.msgs.LogRecord
// (fuzz_record_file rarely gets past the checksums to here). A payload that parses goes through
// record_checks.hpp, then is written with common::RecordWriter and read back with RecordReader:
// the same record must come back, alone and undamaged.
#include <cstddef>
#include <cstdint>
#include <string>

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
  rigid::msgs::LogRecord record;
  if (size > static_cast<std::size_t>(INT32_MAX) ||
      !record.ParseFromArray(data, static_cast<int>(size))) {
    return 0;
  }
  rigid::fuzz::check_record(record);

  const rigid::fuzz::MemoryFile file(nullptr, 0);
  {
    rigid::common::RecordWriter writer(file.path(), /*overwrite=*/true);
    writer.append(record);
    writer.close();
  }
  rigid::common::RecordReader reader(file.path());
  rigid::msgs::LogRecord back;
  require(reader.next(back), "a written record reads back");
  require(back.SerializeAsString() == record.SerializeAsString(), "it reads back unchanged");
  require(!reader.next(back) && !reader.damage(), "it is alone and undamaged");
  return 0;
}
