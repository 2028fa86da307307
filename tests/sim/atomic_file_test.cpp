// Output files appear complete or not at all.
#include "util/atomic_file.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <stdexcept>

#include "test_dir.hpp"

namespace rigid::sim {
namespace {

namespace fs = std::filesystem;
using testing::read_file;
using testing::TestDir;
using testing::write_file;

TEST(AtomicFile, CommitRenamesTheTemporary) {
  const TestDir dir;
  const std::string out = dir.file("out.csv");
  {
    util::AtomicFile f(out);
    EXPECT_EQ(f.tmp_path(), out + ".tmp");
    f.write("hello\n");
    EXPECT_TRUE(fs::exists(out + ".tmp"));
    EXPECT_FALSE(fs::exists(out));
    f.commit();
  }
  EXPECT_EQ(read_file(out), "hello\n");
  EXPECT_FALSE(fs::exists(out + ".tmp"));
}

TEST(AtomicFile, WithoutCommitNothingIsLeftAndTheOldFileIsKept) {
  const TestDir dir;
  const std::string out = dir.file("out.csv");
  write_file(out, "previous\n");
  {
    util::AtomicFile f(out);
    f.write("partial");
  }
  EXPECT_FALSE(fs::exists(out + ".tmp"));
  EXPECT_EQ(read_file(out), "previous\n");
}

TEST(AtomicFile, UncreatableFileNamesIt) {
  const TestDir dir;
  const std::string out = dir.file("missing/out.csv");
  try {
    util::AtomicFile f(out);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(out + ".tmp"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("No such file"), std::string::npos) << e.what();
  }
}

TEST(AtomicFile, FailedRenameRemovesTheTemporary) {
  const TestDir dir;
  const std::string out = dir.file("out");
  fs::create_directories(out + "/occupied");  // a non-empty directory cannot be replaced
  {
    util::AtomicFile f(out);
    f.write("x");
    EXPECT_THROW(f.commit(), std::runtime_error);
  }
  EXPECT_FALSE(fs::exists(out + ".tmp"));
  EXPECT_TRUE(fs::is_directory(out));
}

}  // namespace
}  // namespace rigid::sim
