// CRC-32C (Castagnoli polynomial 0x1EDC6F41, reflected, initial value and final xor 0xFFFFFFFF):
// the checksum of each record in rigid's log files (record_file.hpp). Chosen over CRC-32 for its
// better error detection on the record sizes we write (Castagnoli 1993; it is also what iSCSI,
// ext4 and LevelDB's log use). Table-driven, eight bytes at a time.
#pragma once

#include <cstdint>
#include <span>

namespace rigid::common {

// The CRC of `bytes`; extend a running CRC by passing it as `crc` (crc32c(a + b) ==
// crc32c(b, crc32c(a))).
std::uint32_t crc32c(std::span<const std::uint8_t> bytes, std::uint32_t crc = 0);

}  // namespace rigid::common
