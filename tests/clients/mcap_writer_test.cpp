// The MCAP writer's pieces that the end-to-end test (tests/mcap) cannot isolate: MCAP's CRC-32
// (zlib/IEEE, not CRC-32C) and the combination of CRCs that saves hashing a chunk twice.
#include "record/mcap_writer.hpp"

#include <gtest/gtest.h>

#include <string>

namespace rigid::record {
namespace {

TEST(McapCrc32, IsTheIeeeCrcOfTheCheckString) {
  // The catalogued check value of CRC-32/ISO-HDLC (zlib's crc32) for "123456789".
  EXPECT_EQ(crc32(0, std::string_view("123456789")), 0xCBF43926u);
  EXPECT_EQ(crc32(0, std::string_view()), 0u);
}

TEST(McapCrc32, ContinuesAndCombinesLikeOneRun) {
  std::string bytes;
  for (int i = 0; i < 10007; ++i)
    bytes.push_back(static_cast<char>((i * 131) ^ (i >> 3)));
  const std::uint32_t whole = crc32(0, bytes);
  for (const std::size_t cut : {0u, 1u, 7u, 8u, 9u, 4096u, 10006u, 10007u}) {
    const std::string_view a = std::string_view(bytes).substr(0, cut);
    const std::string_view b = std::string_view(bytes).substr(cut);
    EXPECT_EQ(crc32(crc32(0, a), b), whole) << cut;
    EXPECT_EQ(crc32_combine(crc32(0, a), crc32(0, b), b.size()), whole) << cut;
  }
}

}  // namespace
}  // namespace rigid::record
