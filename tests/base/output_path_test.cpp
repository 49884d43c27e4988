// Outputs that would write over an input: the input itself, a file or directory inside
// it, through "..", a symlink or a hard link; and outputs beside it that merely share a
// prefix of its name.
#include "base/output_path.hpp"

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "tests/support/run_process.hpp"

namespace ccdlane {
namespace {

TEST(OutputPath, TheInputAndWhatLiesInsideIt) {
  test::TempDir dir;
  const std::string rec = dir.file("rec");
  std::filesystem::create_directory(rec);
  dir.write("rec/frames.csv", "file,t_ns\n");
  EXPECT_TRUE(lies_within(rec, rec));
  EXPECT_TRUE(lies_within(rec + "/", rec));
  EXPECT_TRUE(lies_within(rec + "/frames.csv", rec));
  EXPECT_TRUE(lies_within(rec + "/000001.pgm", rec)) << "need not exist";
  EXPECT_TRUE(lies_within(rec + "/overlays/new", rec));
  EXPECT_TRUE(lies_within(dir.file("other/../rec/x.png"), rec));
  std::filesystem::create_directory_symlink(rec, dir.file("link"));
  EXPECT_TRUE(lies_within(dir.file("link/x.png"), rec));
  std::filesystem::create_hard_link(rec + "/frames.csv", dir.file("hard.csv"));
  EXPECT_TRUE(lies_within(dir.file("hard.csv"), rec + "/frames.csv"));
}

TEST(OutputPath, BesideTheInputIsFine) {
  test::TempDir dir;
  const std::string rec = dir.file("rec");
  std::filesystem::create_directory(rec);
  EXPECT_FALSE(lies_within(dir.file("rec2"), rec)) << "a shared prefix is not inside";
  EXPECT_FALSE(lies_within(dir.file("overlays"), rec));
  EXPECT_FALSE(lies_within(dir.path(), rec)) << "the parent holds the input, not the other way round";
  EXPECT_FALSE(lies_within(dir.file("out.jsonl"), dir.file("drive.lcmlog")));
}

}  // namespace
}  // namespace ccdlane
