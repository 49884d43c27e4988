// The learned mount's file: written and read back to the same numbers, every way a file
// can be unusable named, the atomic write leaving no temporary, a failed write saying
// which step failed, and a save that allocates nothing.
#include "daemon/mount_state_file.hpp"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <iterator>
#include <string>

#include <gtest/gtest.h>

#include "daemon/allocation_counter.hpp"
#include "tests/daemon/child_process.hpp"
#include "tests/support/run_process.hpp"

namespace ccdlane {
namespace {

using calibration::LearnedMount;
using calibration::OnlineMountOptions;

OnlineMountOptions options() {
  OnlineMountOptions o;
  o.configured_psi_deg = 0.25;
  o.configured_theta_deg = 4.1;  // not exact in binary: read back bit for bit all the same
  o.max_correction_deg = 3.0;
  return o;
}

// Not all of them exact in binary: read back bit for bit all the same.
const LearnedMount kLearned{{1.375, -1.98765}, {1.25, -1.5}, {0.5, 0.19}, 12345};

std::string text_of(const LearnedMount& m, const OnlineMountOptions& o = options()) {
  char buf[1024];
  const std::size_t n = format_mount_state(m, o, buf, sizeof buf);
  EXPECT_GT(n, 0u);
  return std::string(buf, n);
}

std::string why(const std::string& text) {
  LearnedMount out;
  return parse_mount_state(text, options(), out);
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

TEST(MountStateFile, ReadsBackWhatItWrote) {
  LearnedMount back;
  ASSERT_EQ(parse_mount_state(text_of(kLearned), options(), back), "");
  EXPECT_EQ(back.estimate, kLearned.estimate);
  EXPECT_EQ(back.applied, kLearned.applied);
  EXPECT_EQ(back.spread, kLearned.spread);
  EXPECT_EQ(back.frames, kLearned.frames);
}

TEST(MountStateFile, UnusableFilesSayWhy) {
  const std::string good = text_of(kLearned);
  EXPECT_EQ(why(""), "no format version");
  EXPECT_EQ(why("just words\n"), "line 1 is not \"key = value\"");
  EXPECT_EQ(why(replaced(good, "format = 1", "format = 2")), "format 2.000000, this ccdlaned reads format 1");
  EXPECT_EQ(why(replaced(good, "frames = 12345", "")), "no frames");
  EXPECT_EQ(why(good + "frames = 1\n"), "frames is given twice");
  EXPECT_EQ(why(good + "colour = 1\n"), "unknown key colour");
  EXPECT_EQ(why(replaced(good, "frames = 12345", "frames = lots")), "frames is not a number (line 15)");
  EXPECT_EQ(why(replaced(good, "frames = 12345", "frames = 1.5")), "frames is not a count >= 1");
  EXPECT_EQ(why(replaced(good, "estimate_psi_deg = 1.375", "estimate_psi_deg = nan")),
            "estimate_psi_deg is not finite (line 8)");
  EXPECT_EQ(why(replaced(good, "estimate_psi_deg = 1.375", "estimate_psi_deg = 1e999")),
            "estimate_psi_deg is not a number (line 8)");
  EXPECT_EQ(why(replaced(good, "applied_theta_deg = -1.5", "applied_theta_deg = -3.5")),
            "applied_theta_deg -3.5 lies beyond max_correction_deg 3");
  EXPECT_EQ(why(replaced(good, "spread_psi_deg = 0.5", "spread_psi_deg = -0.5")),
            "spread_psi_deg is not a spread of 0..10 degrees");
  OnlineMountOptions other = options();
  other.configured_psi_deg = 0.5;  // the [attitude] was changed since
  EXPECT_EQ(why(text_of(kLearned, other)),
            "learned against [attitude] psi_deg 0.5 theta_deg 4.1, configured now 0.25 4.1");
}

TEST(MountStateFile, AFormatThatDoesNotFitIsRefused) {
  char small[64];
  EXPECT_EQ(format_mount_state(kLearned, options(), small, sizeof small), 0u);
}

TEST(MountStateFile, WritesAtomicallyAndAllocatesNothing) {
  test::TempDir dir;
  const std::string path = dir.file("mount.toml");
  dir.write("mount.toml", "the old one\n");
  char text[1024];
  const std::size_t n = format_mount_state(kLearned, options(), text, sizeof text);
  const std::uint64_t before = allocation_counter::in_this_thread();
  const FileWriteError e = write_file_atomically(path.c_str(), text, n);
  EXPECT_EQ(allocation_counter::in_this_thread() - before, 0u);
  EXPECT_FALSE(e) << e.step << ": " << std::strerror(e.error);
  EXPECT_EQ(test::read_file(path), std::string(text, n));
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.path()), {}), 1) << "no temporary left";
}

// A symlink at the old temporary name "<state_file>.tmp" once made the daemon overwrite
// its target: the temporary is a new name now, and the link and its target stay as they were.
TEST(MountStateFile, ASymlinkAtTheTemporaryNameIsNotFollowed) {
  test::TempDir dir;
  const std::string path = dir.file("mount.toml");
  dir.write("victim", "not the daemon's\n");
  std::filesystem::create_symlink(dir.file("victim"), path + ".tmp");
  const FileWriteError e = write_file_atomically(path.c_str(), "new\n", 4);
  EXPECT_FALSE(e) << e.step << ": " << std::strerror(e.error);
  EXPECT_EQ(test::read_file(path), "new\n");
  EXPECT_EQ(test::read_file(dir.file("victim")), "not the daemon's\n");
  EXPECT_TRUE(std::filesystem::is_symlink(path + ".tmp"));
}

TEST(MountStateFile, AFailedWriteNamesItsStepAndLeavesNothing) {
  test::TempDir dir;
  const std::string path = dir.file("missing/mount.toml");
  const FileWriteError e = write_file_atomically(path.c_str(), "x", 1);
  ASSERT_TRUE(e);
  EXPECT_STREQ(e.step, "open");
  EXPECT_EQ(e.error, ENOENT);
  // The target a directory: rename fails, the temporary is removed.
  std::filesystem::create_directory(dir.file("taken"));
  std::filesystem::create_directory(dir.file("taken/sub"));
  const std::string target = dir.file("taken");
  const FileWriteError r = write_file_atomically(target.c_str(), "x", 1);
  ASSERT_TRUE(r);
  EXPECT_STREQ(r.step, "rename");
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.path()), {}), 1) << "taken/ only: no temporary left";
}

}  // namespace
}  // namespace ccdlane
