// rigid's log files without a network: CRC-32C against known values, records that come back as
// written, and the crash-safety promise: a file cut at any byte reads back every complete record
// and reports the rest as a damaged tail; a corrupted byte is caught by the checksum. Also the
// state hash, and the lcm-logger reader on a log written here byte by byte.
#include "common/record_file.hpp"

#include <gtest/gtest.h>
#include <zstd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "common/crc32c.hpp"
#include "common/lcm_log.hpp"
#include "common/log_records.hpp"
#include "common/state_hash.hpp"
#include "test_dir.hpp"

namespace rigid::common {
namespace {

using sim::testing::read_file;
using sim::testing::TestDir;
using sim::testing::write_file;

std::span<const std::uint8_t> bytes(const std::string& s) {
  return {reinterpret_cast<const std::uint8_t*>(s.data()), s.size()};
}

TEST(Crc32c, MatchesTheStandardCheckValues) {
  // The CRC-32C catalogue's check value, and RFC 3720's (iSCSI) test vectors.
  EXPECT_EQ(common::crc32c(bytes("123456789")), 0xE3069283u);
  EXPECT_EQ(common::crc32c(bytes(std::string(32, '\0'))), 0x8A9136AAu);
  EXPECT_EQ(common::crc32c(bytes(std::string(32, '\xff'))), 0x62A8AB43u);
  std::string ascending(32, '\0');
  for (int i = 0; i < 32; ++i)
    ascending[static_cast<std::size_t>(i)] = static_cast<char>(i);
  EXPECT_EQ(common::crc32c(bytes(ascending)), 0x46DD794Eu);
  EXPECT_EQ(common::crc32c({}), 0u);
}

TEST(Crc32c, ExtendingARunningCrcEqualsOnePass) {
  std::string text;
  for (int i = 0; i < 1000; ++i)
    text += static_cast<char>(i * 7 + 3);
  for (std::size_t cut : {0u, 1u, 7u, 8u, 9u, 500u, 999u, 1000u}) {
    const std::string a = text.substr(0, cut), b = text.substr(cut);
    EXPECT_EQ(common::crc32c(bytes(b), common::crc32c(bytes(a))), common::crc32c(bytes(text)))
        << cut;
  }
}

rigid::StateFrame sample_state(std::int64_t tick, std::size_t bodies) {
  rigid::StateFrame f;
  f.resize(bodies);
  f.tick = tick;
  f.sim_time = static_cast<double>(tick) * 1e-3;
  for (std::size_t i = 0; i < bodies; ++i) {
    f.ids[i] = static_cast<std::int32_t>(i);
    for (int k = 0; k < 3; ++k) {
      f.position[3 * i + k] = 0.1 * static_cast<double>(tick) + static_cast<double>(i + k) / 3.0;
      f.linear_velocity[3 * i + k] = -1.0 / static_cast<double>(tick + i + k + 1);
      f.angular_velocity[3 * i + k] = 1e-300 * static_cast<double>(k);
    }
    f.orientation[4 * i] = 1.0;
  }
  return f;
}

// Writes `n` state records after the header; returns the byte offset where each record starts
// (and, last, the end of the file).
std::vector<std::uint64_t> write_states(const std::string& path, int n) {
  common::RecordWriter w(path, false);
  std::vector<std::uint64_t> starts{w.bytes()};
  msgs::LogRecord r;
  r.mutable_header()->set_kind(msgs::LogHeader::RECORDING);
  r.mutable_header()->set_software_version(common::software_version());
  w.append(r);
  starts.push_back(w.bytes());
  for (int i = 0; i < n; ++i) {
    common::to_record(sample_state(i, 3), i * 1000, *r.mutable_state());
    w.append(r);
    starts.push_back(w.bytes());
  }
  w.close();
  return starts;
}

int count_records(const std::string& path, std::optional<common::Damage>* damage = nullptr) {
  common::RecordReader reader(path);
  msgs::LogRecord r;
  int n = 0;
  while (reader.next(r))
    ++n;
  if (damage) *damage = reader.damage();
  return n;
}

TEST(RecordFile, RecordsComeBackExactlyAsWritten) {
  TestDir dir;
  const std::string path = dir.file("a.rlog");
  write_states(path, 20);
  common::RecordReader reader(path);
  msgs::LogRecord r;
  ASSERT_TRUE(reader.next(r));
  ASSERT_TRUE(r.has_header());
  EXPECT_EQ(r.header().software_version(), common::software_version());
  for (int i = 0; i < 20; ++i) {
    ASSERT_TRUE(reader.next(r)) << i;
    rigid::StateFrame f;
    ASSERT_TRUE(common::from_record(r.state(), f));
    EXPECT_EQ(f, sample_state(i, 3));
    EXPECT_EQ(r.state().recorded_ns(), i * 1000);
  }
  EXPECT_FALSE(reader.next(r));
  EXPECT_FALSE(reader.damage());
  EXPECT_EQ(reader.offset(), reader.size());
}

TEST(RecordFile, StatsRecordsKeepEveryField) {
  // A distinct value in every field, so that a field dropped or swapped on the way shows.
  rigid::StatsReport s;
  s.tick = 1;
  s.sim_time = 2.5;
  s.mode = rigid::Mode::kLockstep;
  s.paused = true;
  s.rtf_last_second = 3.5;
  s.rtf_since_start = 4.5;
  s.lateness_p50_us = 5.5;
  s.lateness_p99_us = 6.5;
  s.lateness_max_us = 7.5;
  s.overruns = 8;
  s.step_cost_p50_us = 9.5;
  s.step_cost_max_us = 10.5;
  s.bodies_frozen = 11;
  s.large_rotation_steps = 12;
  s.states_skipped = 13;
  s.commands_accepted = 14;
  s.rejected = {15, 16, 17, 18, 19, 20, 21};
  s.dds = {22, 23, 24, 25};
  s.lcm = {26, 27, 28, 29};
  msgs::StatsRecord record;
  common::to_record(s, 30, record);
  msgs::StatsRecord parsed;
  ASSERT_TRUE(parsed.ParseFromString(record.SerializeAsString()));
  EXPECT_EQ(parsed.recorded_ns(), 30);
  rigid::StatsReport back;
  common::from_record(parsed, back);
  EXPECT_EQ(back, s);
}

// A distinct value in every field of a tick's contact events, through the record's bytes and back.
TEST(RecordFile, ContactRecordsKeepEveryField) {
  rigid::ContactEvents c;
  c.tick = 41;
  c.sim_time = 0.041;
  c.stamp_ns = 1'700'000'000'123'456'789;
  c.dropped = 3;
  c.resize(2);
  c.kinds = {rigid::ContactKind::kImpact, rigid::ContactKind::kSeparate};
  c.bodies = {4, 5};
  c.parts = {0, 2};
  c.times = {0.0405, std::nextafter(0.041, 0.0)};
  for (std::size_t k = 0; k < 6; ++k) {
    c.position[k] = 1.0 + static_cast<double>(k) / 7.0;
    c.normal[k] = -0.5 * static_cast<double>(k);
    c.impulse[k] = 1e-300 * static_cast<double>(k + 1);
  }
  msgs::ContactRecord record;
  common::to_record(c, 77, record);
  msgs::ContactRecord parsed;
  ASSERT_TRUE(parsed.ParseFromString(record.SerializeAsString()));
  EXPECT_EQ(parsed.recorded_ns(), 77);
  rigid::ContactEvents back;
  ASSERT_TRUE(common::from_record(parsed, back));
  EXPECT_EQ(back, c);
  // Per-event arrays that disagree are refused, and so are more events than a message carries.
  parsed.mutable_normal()->RemoveLast();
  EXPECT_FALSE(common::from_record(parsed, back));
  msgs::ContactRecord big;
  for (std::size_t i = 0; i <= rigid::kMaxContactEvents; ++i) {
    big.add_kinds(1);
    big.add_bodies(0);
    big.add_parts(0);
    big.add_times(0.0);
    for (int k = 0; k < 3; ++k) {
      big.add_position(0.0);
      big.add_normal(0.0);
      big.add_impulse(0.0);
    }
  }
  EXPECT_FALSE(common::from_record(big, back));
}

// A scene's static parts, through a SceneRecord and back.
TEST(RecordFile, SceneRecordsKeepTheStaticParts) {
  rigid::SceneDescription d;
  d.scene_name = "s";
  d.ids = {0};
  d.names = {"ball"};
  d.masses = {1.5};
  d.inertia = {1, 2, 3, 4, 5, 6};
  d.shape_kinds = {rigid::ShapeKind::kSphere};
  d.shape_dims = {0.1, 0, 0};
  d.part_names = {"ground", "ramp"};
  d.part_kinds = {rigid::ShapeKind::kPlane, rigid::ShapeKind::kBox};
  d.part_position = {0, 0, -1, 1, 2, 3};
  d.part_orientation = {1, 0, 0, 0, 0.8, 0, 0.6, 0};
  d.part_dims = {0, 0, 0, 2, 1, 0.1};
  d.part_restitution = {0.5, 0.25};
  d.part_friction = {0.75, 0.2};
  ASSERT_TRUE(d.lengths_agree());
  msgs::SceneRecord record;
  common::to_record(d, 5, record);
  msgs::SceneRecord parsed;
  ASSERT_TRUE(parsed.ParseFromString(record.SerializeAsString()));
  rigid::SceneDescription back;
  ASSERT_TRUE(common::from_record(parsed, back));
  EXPECT_EQ(back, d);
  parsed.mutable_part_friction()->RemoveLast();
  EXPECT_FALSE(common::from_record(parsed, back));
}

TEST(RecordFile, AFileCutAtAnyByteReadsEveryCompleteRecordAndReportsTheTail) {
  // What a writer killed mid-write leaves: every prefix of a valid file.
  TestDir dir;
  const std::string path = dir.file("full.rlog");
  const std::vector<std::uint64_t> starts = write_states(path, 4);
  const std::string full = read_file(path);
  ASSERT_EQ(full.size(), starts.back());
  const std::string cut = dir.file("cut.rlog");
  for (std::uint64_t size = common::kLogPreambleBytes; size <= full.size(); ++size) {
    write_file(cut, full.substr(0, size));
    std::optional<common::Damage> damage;
    const int n = count_records(cut, &damage);
    // The records that fit entirely in `size` bytes.
    int complete = 0;
    while (static_cast<std::size_t>(complete) + 1 < starts.size() &&
           starts[static_cast<std::size_t>(complete) + 1] <= size)
      ++complete;
    EXPECT_EQ(n, complete) << "cut at " << size;
    const std::uint64_t intact = starts[static_cast<std::size_t>(complete)];
    if (size == intact) {
      EXPECT_FALSE(damage) << "cut at " << size << " (a record boundary)";
    } else {
      ASSERT_TRUE(damage) << "cut at " << size;
      EXPECT_EQ(damage->offset, intact) << "cut at " << size;
      EXPECT_EQ(damage->bytes, size - intact);
      EXPECT_NE(damage->reason.find("cut short"), std::string::npos) << damage->reason;
    }
  }
}

TEST(RecordFile, ACorruptedByteIsCaughtByTheChecksum) {
  TestDir dir;
  const std::string path = dir.file("a.rlog");
  const std::vector<std::uint64_t> starts = write_states(path, 5);
  const std::string good = read_file(path);
  // Every byte of the third state record (index 3: header, then states 0, 1, 2), one at a time.
  for (std::uint64_t at = starts[3]; at < starts[4]; ++at) {
    std::string bad = good;
    bad[at] = static_cast<char>(bad[at] ^ 0x10);
    write_file(path, bad);
    std::optional<common::Damage> damage;
    EXPECT_EQ(count_records(path, &damage), 3) << "byte " << at;
    ASSERT_TRUE(damage);
    EXPECT_EQ(damage->offset, starts[3]);
  }
}

TEST(RecordFile, AnExistingFileIsRefusedUnlessOverwriting) {
  TestDir dir;
  const std::string path = dir.file("a.rlog");
  write_file(path, "precious");
  try {
    common::RecordWriter w(path, false);
    FAIL() << "overwrote an existing file";
  } catch (const common::LogFileError& e) {
    EXPECT_EQ(std::string(e.what()), path + ": exists (remove it or choose another name)");
  }
  EXPECT_EQ(read_file(path), "precious");
  common::RecordWriter w(path, true);
  w.close();
  EXPECT_EQ(count_records(path), 0);
}

TEST(RecordFile, NotALogFileIsRefusedWithOneLine) {
  TestDir dir;
  const std::string path = dir.file("a.txt");
  write_file(path, "hello, world");
  EXPECT_THROW(common::RecordReader{path}, common::LogFileError);
  write_file(path, std::string("\xED\xA1\xDA\x01", 4) + std::string(40, '\0'));
  try {
    common::RecordReader reader(path);
    FAIL();
  } catch (const common::LogFileError& e) {
    EXPECT_NE(std::string(e.what()).find("lcm-logger"), std::string::npos) << e.what();
  }
  EXPECT_THROW(common::RecordReader{dir.file("missing")}, common::LogFileError);
  std::string future = "RIGIDLOG";
  future += std::string("\x03\0\0\0", 4);
  write_file(path, future);
  try {
    common::RecordReader reader(path);
    FAIL();
  } catch (const common::LogFileError& e) {
    EXPECT_NE(std::string(e.what()).find("version 3"), std::string::npos) << e.what();
  }
}

// Format 2: records in zstd chunks.

common::Compression zstd() {
  common::Compression c;
  c.zstd = true;
  return c;
}

// A recording of a header and `n` states of `bodies` bodies, each state written as `write` does
// it; `flush_every`: a flush (which seals the open chunk) after every so many states (0: none).
void write_chunked(const std::string& path, int n, std::size_t bodies, int flush_every,
                   common::Compression compression = zstd()) {
  common::RecordWriter w(path, true, compression);
  msgs::LogRecord r;
  r.mutable_header()->set_kind(msgs::LogHeader::RECORDING);
  w.append(r);
  for (int i = 0; i < n; ++i) {
    common::to_record(sample_state(i, bodies), i, *r.mutable_state());
    w.append(r);
    if (flush_every > 0 && (i + 1) % flush_every == 0) w.flush();
  }
  w.close();
}

// The states a file holds, in order, and how it ends.
std::vector<rigid::StateFrame> read_states(const std::string& path,
                                           std::optional<common::Damage>* damage = nullptr,
                                           std::int64_t* chunks = nullptr) {
  common::RecordReader reader(path);
  std::vector<rigid::StateFrame> states;
  msgs::LogRecord r;
  while (reader.next(r)) {
    if (!r.has_state()) continue;
    rigid::StateFrame f;
    EXPECT_TRUE(common::from_record(r.state(), f));
    states.push_back(f);
  }
  if (damage) *damage = reader.damage();
  if (chunks) *chunks = reader.chunks();
  return states;
}

TEST(RecordFileChunks, RecordsComeBackExactlyAsWrittenAndTheFileIsSmaller) {
  TestDir dir;
  const std::string plain = dir.file("plain.rlog"), packed = dir.file("packed.rlog");
  // 400 states of 100 bodies: about 4 MB of records, so chunks are sealed by size (1 MiB) too.
  write_chunked(plain, 400, 100, 10, common::Compression{});
  write_chunked(packed, 400, 100, 10);
  std::optional<common::Damage> damage;
  std::int64_t chunks = 0;
  const std::vector<rigid::StateFrame> states = read_states(packed, &damage, &chunks);
  EXPECT_FALSE(damage);
  EXPECT_EQ(chunks, 40);  // one per flush: 10 states of ~10 kB stay below 1 MiB
  ASSERT_EQ(states.size(), 400u);
  for (int i = 0; i < 400; ++i)
    ASSERT_EQ(states[static_cast<std::size_t>(i)], sample_state(i, 100)) << i;
  EXPECT_EQ(read_states(plain), states);
  EXPECT_LT(std::filesystem::file_size(packed), std::filesystem::file_size(plain) * 3 / 4);
  // The preamble says which format.
  EXPECT_EQ(read_file(packed).substr(8, 4), std::string("\x02\0\0\0", 4));
  EXPECT_EQ(read_file(plain).substr(8, 4), std::string("\x01\0\0\0", 4));
  // Without flushes, chunks are sealed at 1 MiB of records.
  write_chunked(packed, 400, 100, 0);
  EXPECT_EQ(read_states(packed, &damage, &chunks), states);
  EXPECT_FALSE(damage);
  EXPECT_GE(chunks, 4);
  EXPECT_LE(chunks, 5);
}

// Where each chunk of a file of chunks ends: where the reader's offset moves on.
std::vector<std::uint64_t> chunk_ends(const std::string& path) {
  common::RecordReader reader(path);
  std::vector<std::uint64_t> ends;
  std::uint64_t at = reader.offset();
  msgs::LogRecord r;
  while (reader.next(r)) {
    if (reader.offset() != at) ends.push_back(reader.offset());
    at = reader.offset();
  }
  EXPECT_EQ(static_cast<std::size_t>(reader.chunks()), ends.size());
  return ends;
}

TEST(RecordFileChunks, AFileCutAtAnyByteReadsEveryCompleteChunkAndReportsTheTail) {
  TestDir dir;
  const std::string path = dir.file("full.rlog");
  write_chunked(path, 12, 3, 4);  // the header and states 0-3, states 4-7, states 8-11
  const std::string full = read_file(path);
  // Where each chunk starts and ends: the offsets the reader passes.
  const std::vector<std::uint64_t> ends = chunk_ends(path);
  ASSERT_EQ(ends.size(), 3u);
  ASSERT_EQ(ends.back(), full.size());
  const std::string cut = dir.file("cut.rlog");
  for (std::uint64_t size = common::kLogPreambleBytes; size <= full.size(); ++size) {
    write_file(cut, full.substr(0, size));
    std::optional<common::Damage> damage;
    const std::vector<rigid::StateFrame> states = read_states(cut, &damage);
    std::size_t whole = 0;  // chunks entirely within `size` bytes
    while (whole < ends.size() && ends[whole] <= size)
      ++whole;
    EXPECT_EQ(states.size(), 4 * whole) << "cut at " << size;
    const std::uint64_t intact = whole == 0 ? common::kLogPreambleBytes : ends[whole - 1];
    if (size == intact) {
      EXPECT_FALSE(damage) << "cut at " << size;
    } else {
      ASSERT_TRUE(damage) << "cut at " << size;
      EXPECT_EQ(damage->offset, intact) << "cut at " << size;
      EXPECT_EQ(damage->bytes, size - intact);
      EXPECT_NE(damage->reason.find("cut short"), std::string::npos) << damage->reason;
    }
  }
}

TEST(RecordFileChunks, ACorruptedByteAnywhereInAChunkDamagesItWhole) {
  TestDir dir;
  const std::string path = dir.file("a.rlog");
  write_chunked(path, 12, 3, 4);
  const std::string good = read_file(path);
  const std::vector<std::uint64_t> ends = chunk_ends(path);
  ASSERT_EQ(ends.size(), 3u);
  // Every byte of the second chunk: states 0-3 read, then damage at the chunk's start.
  for (std::uint64_t at = ends[0]; at < ends[1]; ++at) {
    std::string bad = good;
    bad[at] = static_cast<char>(bad[at] ^ 0x10);
    write_file(path, bad);
    std::optional<common::Damage> damage;
    EXPECT_EQ(read_states(path, &damage).size(), 4u) << "byte " << at;
    ASSERT_TRUE(damage) << "byte " << at;
    EXPECT_EQ(damage->offset, ends[0]) << "byte " << at;
  }
}

// A chunk whose content lies (a writer's bug, or a forged file whose outer checksum was made to
// match): caught inside, as damage at the chunk's start, before any of its records is returned.
TEST(RecordFileChunks, AChunkIsCheckedWholeBeforeItsFirstRecord) {
  TestDir dir;
  const std::string path = dir.file("forged.rlog");
  // Frames as a writer frames them, and a chunk frame around zstd bytes.
  const auto u32 = [](std::uint32_t v) {
    std::string b(4, '\0');
    for (int i = 0; i < 4; ++i)
      b[static_cast<std::size_t>(i)] = static_cast<char>((v >> (8 * i)) & 0xFF);
    return b;
  };
  const auto frame = [&](const std::string& payload, bool chunk) {
    const std::string length =
        u32(static_cast<std::uint32_t>(payload.size()) | (chunk ? common::kChunkFlag : 0u));
    return length + u32(crc32c(bytes(payload), crc32c(bytes(length)))) + payload;
  };
  msgs::LogRecord r;
  common::to_record(sample_state(1, 2), 0, *r.mutable_state());
  const std::string record = frame(r.SerializeAsString(), false);
  const std::string preamble = std::string("RIGIDLOG") + u32(2);
  const auto chunk_of = [&](const std::string& content) {
    std::string out(ZSTD_compressBound(content.size()), '\0');
    out.resize(ZSTD_compress(out.data(), out.size(), content.data(), content.size(), 3));
    return frame(out, true);
  };
  const std::string good =
      preamble + frame(r.SerializeAsString(), false) + chunk_of(record + record);
  write_file(path, good);
  std::optional<common::Damage> damage;
  EXPECT_EQ(read_states(path, &damage).size(), 3u);
  EXPECT_FALSE(damage);
  std::string inner_bad = record;
  inner_bad[10] = static_cast<char>(inner_bad[10] ^ 1);  // in the payload: its checksum fails
  for (const auto& [content, reason] : std::vector<std::pair<std::string, std::string>>{
           {record + inner_bad, "checksum mismatch inside a chunk"},
           {record + record.substr(0, 5), "a chunk that ends inside a frame header"},
           {record + record.substr(0, record.size() - 1), "a chunk that ends inside a record"}}) {
    write_file(path, preamble + record + chunk_of(content));
    EXPECT_EQ(read_states(path, &damage).size(), 1u) << reason;  // the plain record only
    ASSERT_TRUE(damage) << reason;
    EXPECT_EQ(damage->offset, preamble.size() + record.size()) << reason;
    EXPECT_EQ(damage->reason.rfind(reason, 0), 0u) << damage->reason;
  }
  // Not zstd at all, and a chunk flag in format 1 (an implausible length there, as it always was).
  write_file(path, preamble + record + frame("not zstd", true));
  EXPECT_EQ(read_states(path, &damage).size(), 1u);
  ASSERT_TRUE(damage);
  EXPECT_EQ(damage->reason, "a chunk that is not a zstd frame");
  write_file(path, std::string("RIGIDLOG") + u32(1) + record + chunk_of(record));
  EXPECT_EQ(read_states(path, &damage).size(), 1u);
  ASSERT_TRUE(damage);
  EXPECT_NE(damage->reason.find("implausible record length"), std::string::npos) << damage->reason;
}

TEST(RecordFileChunks, RecordsThatWouldNotShrinkAreWrittenAsPlainFrames) {
  TestDir dir;
  const std::string path = dir.file("noise.rlog");
  // States of random doubles, each flushed alone: zstd cannot shrink random bits.
  {
    common::RecordWriter w(path, true, zstd());
    std::uint64_t x = 88172645463325252ull;
    msgs::LogRecord r;
    for (int i = 0; i < 5; ++i) {
      rigid::StateFrame f = sample_state(i, 4);
      for (std::vector<double>* v :
           {&f.position, &f.orientation, &f.linear_velocity, &f.angular_velocity}) {
        for (double& value : *v) {
          x ^= x << 13, x ^= x >> 7, x ^= x << 17;  // xorshift64
          std::uint64_t bits = (x >> 12) | 0x3FF0000000000000ull;
          std::memcpy(&value, &bits, sizeof bits);
        }
      }
      common::to_record(f, i, *r.mutable_state());
      w.append(r);
      w.flush();
    }
    EXPECT_EQ(w.bytes(), w.record_bytes() + common::kLogPreambleBytes);
  }
  std::optional<common::Damage> damage;
  std::int64_t chunks = -1;
  EXPECT_EQ(read_states(path, &damage, &chunks).size(), 5u);
  EXPECT_FALSE(damage);
  EXPECT_EQ(chunks, 0);
}

TEST(StateHash, EqualStatesHashEquallyAndAnyChangedValueChangesIt) {
  const rigid::StateFrame a = sample_state(7, 4);
  EXPECT_EQ(state_hash(a), state_hash(sample_state(7, 4)));
  EXPECT_NE(state_hash(a), state_hash(sample_state(8, 4)));
  const std::uint64_t h = state_hash(a);
  for (std::vector<double> rigid::StateFrame::*field :
       {&rigid::StateFrame::position, &rigid::StateFrame::orientation,
        &rigid::StateFrame::linear_velocity, &rigid::StateFrame::angular_velocity}) {
    for (std::size_t i = 0; i < (a.*field).size(); ++i) {
      rigid::StateFrame b = a;
      // The smallest change there is: one ulp.
      (b.*field)[i] = std::nextafter((b.*field)[i], 1e300);
      EXPECT_NE(state_hash(b), h) << i;
    }
  }
  // -0 and +0 are different bits, and a replay that differs there is not bit-identical.
  rigid::StateFrame z = a;
  z.orientation[1] = -0.0;
  EXPECT_NE(state_hash(z), h);
}

// An lcm-logger event, big-endian (the format common/lcm_log.hpp reads).
std::string lcm_event(std::int64_t number, std::int64_t us, const std::string& channel,
                      const std::string& data) {
  std::string e;
  const auto put = [&](std::uint64_t v, int n) {
    for (int i = n - 1; i >= 0; --i)
      e += static_cast<char>((v >> (8 * i)) & 0xFF);
  };
  put(0xEDA1DA01, 4);
  put(static_cast<std::uint64_t>(number), 8);
  put(static_cast<std::uint64_t>(us), 8);
  put(channel.size(), 4);
  put(data.size(), 4);
  return e + channel + data;
}

TEST(LcmLog, EventsComeBackAndACutTailIsReported) {
  TestDir dir;
  const std::string path = dir.file("lcm.log");
  const std::string log = lcm_event(0, 1000, "RIGID_STATE", "abc") +
                          lcm_event(1, 2000, "X_RIGID_SCENE", std::string(300, 'z')) +
                          lcm_event(2, 3000, "RIGID_STATE", "");
  write_file(path, log);
  {
    common::LcmLogReader reader(path);
    common::LcmEvent e;
    ASSERT_TRUE(reader.next(e));
    EXPECT_EQ(e.number, 0);
    EXPECT_EQ(e.timestamp_us, 1000);
    EXPECT_EQ(e.channel, "RIGID_STATE");
    EXPECT_EQ(std::string(e.data.begin(), e.data.end()), "abc");
    ASSERT_TRUE(reader.next(e));
    EXPECT_EQ(e.channel, "X_RIGID_SCENE");
    EXPECT_EQ(e.data.size(), 300u);
    ASSERT_TRUE(reader.next(e));
    EXPECT_TRUE(e.data.empty());
    EXPECT_FALSE(reader.next(e));
    EXPECT_FALSE(reader.damage());
  }
  write_file(path, log.substr(0, log.size() - 40));
  common::LcmLogReader reader(path);
  common::LcmEvent e;
  int n = 0;
  while (reader.next(e))
    ++n;
  EXPECT_EQ(n, 1);
  ASSERT_TRUE(reader.damage());
  EXPECT_NE(reader.damage()->reason.find("cut short"), std::string::npos);
}

}  // namespace
}  // namespace rigid::common
