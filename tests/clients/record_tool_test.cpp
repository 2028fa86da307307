// rigid-record as a program on files made here, without a network: what it refuses (a journal or
// a file without states for --csv, an existing OUT for record), how info sums up a large scene,
// and that a compressed recording (format 2) reads back as the same states as a plain one.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "common/log_records.hpp"
#include "common/record_file.hpp"
#include "record/decimation.hpp"
#include "rigidd_process.hpp"
#include "test_dir.hpp"

namespace rigid::record {
namespace {

using rigidd::testing::Completed;
using rigidd::testing::count_lines;
using rigidd::testing::run_program_to_exit;
using sim::testing::read_file;
using sim::testing::TestDir;
using sim::testing::write_file;

rigid::SceneDescription scene_of(std::size_t bodies) {
  rigid::SceneDescription scene;
  scene.scene_name = "many";
  scene.dt = 0.001;
  scene.publish_every = 10;
  for (std::size_t i = 0; i < bodies; ++i) {
    scene.ids.push_back(static_cast<std::int32_t>(i));
    scene.names.push_back("b" + std::to_string(i));
    scene.masses.push_back(1.0);
    scene.inertia.insert(scene.inertia.end(), {1, 1, 1, 0, 0, 0});
    scene.shape_kinds.push_back(rigid::ShapeKind::kNone);
    scene.shape_dims.insert(scene.shape_dims.end(), {0, 0, 0});
  }
  return scene;
}

// A recording (or a journal: kind JOURNAL, its state hashes instead of states) of `states` states
// of `bodies` bodies.
void write_log(const std::string& path, std::size_t bodies, int states,
               common::Compression compression = {},
               msgs::LogHeader::Kind kind = msgs::LogHeader::RECORDING) {
  common::RecordWriter w(path, true, compression);
  msgs::LogRecord r;
  r.mutable_header()->set_kind(kind);
  r.mutable_header()->set_software_version(common::software_version());
  common::to_record(scene_of(bodies), 0, *r.mutable_header()->mutable_scene());
  w.append(r);
  for (int i = 0; i < states; ++i) {
    if (kind == msgs::LogHeader::JOURNAL) {
      r.mutable_state_hash()->set_tick(10 * i);
      r.mutable_state_hash()->set_hash(static_cast<std::uint64_t>(i) * 2654435761u);
    } else {
      rigid::StateFrame f;
      f.resize(bodies);
      f.tick = 10 * i;
      f.sim_time = 0.01 * i;
      for (std::size_t b = 0; b < bodies; ++b) {
        f.ids[b] = static_cast<std::int32_t>(b);
        f.position[3 * b] = 0.5 * i + static_cast<double>(b);
        f.orientation[4 * b] = 1.0;
      }
      common::to_record(f, 1'000'000 * i, *r.mutable_state());
    }
    w.append(r);
  }
  msgs::LogRecord end;
  end.mutable_end()->set_records(w.records());
  w.append(end);
  w.close();
}

// --every: one state in N publication periods; without it (N = 1) every state, those rigidd
// publishes off the period after a new wrench included.
TEST(RigidRecordDecimation, KeepsTicksOnMultiplesOfNPeriodsAndEveryStateForOne) {
  rigid::SceneDescription scene;
  scene.publish_every = 10;
  Decimation all(1), fifth(5);
  all.scene(scene);
  fifth.scene(scene);
  for (const std::int64_t tick : {0, 10, 13, 50, 57, 100})
    EXPECT_TRUE(all.keep(tick)) << tick;
  for (const std::int64_t tick : {0, 50, 100, 250})
    EXPECT_TRUE(fifth.keep(tick)) << tick;
  for (const std::int64_t tick : {10, 13, 40, 60, 105})
    EXPECT_FALSE(fifth.keep(tick)) << tick;
  scene.publish_every = 1;  // a new scene: its period counts
  fifth.scene(scene);
  EXPECT_TRUE(fifth.keep(5));
  EXPECT_FALSE(fifth.keep(10 + 3));
}

TEST(RigidRecordTool, ExportToCsvRefusesAJournalAndAFileWithoutStates) {
  TestDir dir;
  const std::string journal = dir.file("run.journal"), empty = dir.file("empty.rlog");
  write_log(journal, 3, 5, {}, msgs::LogHeader::JOURNAL);
  write_log(empty, 3, 0);
  for (const auto& [in, says] : std::vector<std::pair<std::string, std::string>>{
           {journal, journal + " is a journal (rigidd --journal): it holds accepted commands "
                               "and state hashes, no states; replay it with rigid-sim --replay"},
           {empty, empty + ": no states to export"}}) {
    const std::string csv = dir.file("out.csv");
    const Completed r = run_program_to_exit(RIGID_RECORD_EXE, {"export", in, "--csv", csv});
    EXPECT_EQ(r.exit_code, 1) << in;
    EXPECT_EQ(count_lines(r.err), 1) << r.err;
    EXPECT_EQ(r.err.rfind("rigid-record: " + says, 0), 0u) << r.err;
    EXPECT_FALSE(std::filesystem::exists(csv)) << in;
    EXPECT_FALSE(std::filesystem::exists(csv + ".tmp")) << in;
  }
}

TEST(RigidRecordTool, RecordOntoAnExistingFileSaysForceOverwritesIt) {
  TestDir dir;
  const std::string out = dir.file("taken.rlog");
  write_file(out, "precious");
  // The file is checked before any bus is joined: no rigidd is needed to be refused.
  const Completed r = run_program_to_exit(
      RIGID_RECORD_EXE, {"record", out, "--timeout", "0.5", "--prefix", "nobody_here"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.err, "rigid-record: " + out + " already exists (--force overwrites it)\n");
  EXPECT_EQ(read_file(out), "precious");
}

TEST(RigidRecordTool, InfoSumsUpTheBodiesOfALargeScene) {
  TestDir dir;
  const std::string file = dir.file("many.rlog");
  write_log(file, 1000, 2);
  const Completed r = run_program_to_exit(RIGID_RECORD_EXE, {"info", file});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::size_t at = r.out.find("scene many: ");
  ASSERT_NE(at, std::string::npos) << r.out;
  const std::string line = r.out.substr(at, r.out.find('\n', at) - at);
  EXPECT_EQ(
      line.rfind("scene many: 1000 bodies (b0, b1, b2, b3, b4, b5, ... 993 more ..., b999), ", 0),
      0u)
      << line;
  EXPECT_LT(line.size(), 200u) << line;
  // A small scene is named in full.
  write_log(file, 8, 2);
  const Completed small = run_program_to_exit(RIGID_RECORD_EXE, {"info", file});
  EXPECT_NE(small.out.find("8 bodies (b0, b1, b2, b3, b4, b5, b6, b7), "), std::string::npos)
      << small.out;
}

TEST(RigidRecordTool, ACompressedRecordingReadsBackAsThePlainOne) {
  TestDir dir;
  const std::string plain = dir.file("plain.rlog"), packed = dir.file("packed.rlog");
  common::Compression zstd;
  zstd.zstd = true;
  write_log(plain, 50, 300);
  write_log(packed, 50, 300, zstd);
  const Completed info = run_program_to_exit(RIGID_RECORD_EXE, {"info", packed});
  ASSERT_EQ(info.exit_code, 0) << info.err;
  EXPECT_NE(info.out.find("rigid log (format 2, zstd chunks), "), std::string::npos) << info.out;
  EXPECT_NE(info.out.find(" complete records (2 chunks: "), std::string::npos) << info.out;
  EXPECT_NE(info.out.find("records: 300 states"), std::string::npos) << info.out;
  EXPECT_NE(info.out.find("ends cleanly"), std::string::npos) << info.out;
  const Completed plain_info = run_program_to_exit(RIGID_RECORD_EXE, {"info", plain});
  EXPECT_NE(plain_info.out.find("rigid log (format 1), "), std::string::npos) << plain_info.out;
  for (const std::string& f : {plain, packed}) {
    const Completed e = run_program_to_exit(RIGID_RECORD_EXE, {"export", f, "--csv", f + ".csv"});
    ASSERT_EQ(e.exit_code, 0) << e.err;
  }
  const std::string csv = read_file(plain + ".csv");
  EXPECT_EQ(count_lines(csv), 1 + 300 * 50);
  EXPECT_EQ(read_file(packed + ".csv"), csv);
}

}  // namespace
}  // namespace rigid::record
