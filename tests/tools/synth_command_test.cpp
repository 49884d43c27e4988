// `ccdlane synth` as a user runs it: a frame directory with the documented columns,
// deterministic per seed, and bad input refused with one line and nothing left behind.
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "drivers/frames/frame_directory.hpp"
#include "tests/support/run_process.hpp"

namespace ccdlane {
namespace {

const std::string kTool = CCDLANE_TOOL;

// The reference camera at half resolution (same field of view), for speed.
const char* kSmallCamera = R"([camera]
U_mm = 6.4
V_mm = 4.8
Uc_mm = 0.0084
Vc_mm = 0.0084
Nu = 400
Nv = 300
f_mm = 5.05
k_px2 = -3.32e-6
[attitude]
theta_deg = 3.0
)";

TEST(SynthCommand, WritesAFrameDirectoryWithTruth) {
  test::TempDir dir;
  const std::string config = dir.write("cam.toml", kSmallCamera);
  const auto r =
      test::run_process({kTool, "synth", config, "--out", dir.file("road"), "--frames", "4", "--lanes", "4"});
  ASSERT_EQ(r.exit_status, 0) << r.err;
  EXPECT_TRUE(r.out.empty());
  EXPECT_NE(r.err.find("wrote 4 frames of 400x300 (8-bit)"), std::string::npos) << r.err;
  FrameDirectory frames(dir.file("road"));
  ASSERT_EQ(frames.size(), 4u);
  EXPECT_TRUE(frames.has_gyro_columns());
  EXPECT_EQ(frames.truth_columns().size(), 9u + 5u);  // attitude, lane, and 5 lines
  EXPECT_EQ(frames.truth_columns().back(), "truth_y0_4_mm");
  EXPECT_EQ(frames.row(3).t_ns, 100'000'000);
  EXPECT_NEAR(*frames.truth(0, "truth_theta_deg"), 3.0, 0.5);
  EXPECT_EQ(*frames.truth(2, "truth_ego_lane"), 1.0);
  EXPECT_NEAR(*frames.truth(1, "truth_y0_1_mm") - *frames.truth(1, "truth_y0_2_mm"), 3600.0, 1e-6);
  const auto header = frames.probe_first();
  ASSERT_TRUE(header);
  EXPECT_EQ(header->width, 400);
  EXPECT_EQ(header->maxval, 255);
  EXPECT_FALSE(std::filesystem::exists(dir.file("road/frames.csv.tmp")));
}

TEST(SynthCommand, SameSeedSameBytesOtherSeedOtherBytes) {
  test::TempDir dir;
  const std::string config = dir.write("cam.toml", kSmallCamera);
  for (const char* out : {"a", "b"})
    ASSERT_EQ(
        test::run_process({kTool, "synth", config, "--out", dir.file(out), "--frames", "2", "--seed", "5"}).exit_status,
        0);
  ASSERT_EQ(
      test::run_process({kTool, "synth", config, "--out", dir.file("c"), "--frames", "2", "--seed", "6"}).exit_status,
      0);
  EXPECT_EQ(test::read_file(dir.file("a/000001.pgm")), test::read_file(dir.file("b/000001.pgm")));
  EXPECT_EQ(test::read_file(dir.file("a/frames.csv")), test::read_file(dir.file("b/frames.csv")));
  EXPECT_NE(test::read_file(dir.file("a/000001.pgm")), test::read_file(dir.file("c/000001.pgm")));
}

// --night and --cars render what [synth] night and cars do, byte for byte.
TEST(SynthCommand, NightAndCarsFromTheCommandLineAreTheConfigurations) {
  test::TempDir dir;
  const std::string flags = dir.write("cam.toml", kSmallCamera);
  const std::string keys = dir.write("keys.toml", std::string(kSmallCamera) + "[synth]\nnight = true\ncars = 3\n");
  ASSERT_EQ(
      test::run_process({kTool, "synth", flags, "--out", dir.file("f"), "--frames", "2", "--night", "--cars", "3"})
          .exit_status,
      0);
  ASSERT_EQ(test::run_process({kTool, "synth", keys, "--out", dir.file("k"), "--frames", "2"}).exit_status, 0);
  ASSERT_EQ(test::run_process({kTool, "synth", flags, "--out", dir.file("d"), "--frames", "2"}).exit_status, 0);
  EXPECT_EQ(test::read_file(dir.file("f/000001.pgm")), test::read_file(dir.file("k/000001.pgm")));
  EXPECT_NE(test::read_file(dir.file("f/000001.pgm")), test::read_file(dir.file("d/000001.pgm")));
  const auto bad = test::run_process({kTool, "synth", flags, "--out", dir.file("b"), "--cars", "9"});
  EXPECT_EQ(bad.exit_status, 2) << bad.err;
  EXPECT_FALSE(std::filesystem::exists(dir.file("b")));
}

TEST(SynthCommand, SixteenBitWithoutGyro) {
  test::TempDir dir;
  const std::string config = dir.write("cam.toml", kSmallCamera);
  const auto r =
      test::run_process({kTool, "synth", config, "--out", dir.file("w"), "--frames", "1", "--bits", "12", "--no-gyro"});
  ASSERT_EQ(r.exit_status, 0) << r.err;
  FrameDirectory frames(dir.file("w"));
  EXPECT_FALSE(frames.has_gyro_columns());
  EXPECT_EQ(frames.probe_first()->maxval, 4095);
}

TEST(SynthCommand, BadInputIsOneLineExitTwoAndLeavesNothing) {
  test::TempDir dir;
  const std::string config = dir.write("cam.toml", kSmallCamera);
  const std::string bad = dir.write("bad.toml", std::string(kSmallCamera) + "[synth]\nlanes = 9\n");
  auto r = test::run_process({kTool, "synth", bad, "--out", dir.file("x")});
  EXPECT_EQ(r.exit_status, 2);
  EXPECT_EQ(r.err, "ccdlane: " + bad + ":13: synth.lanes: must be 2..4, got 9\n");
  EXPECT_FALSE(std::filesystem::exists(dir.file("x")));

  dir.write("frames.csv", "file,t_ns\n");
  r = test::run_process({kTool, "synth", config, "--out", dir.path(), "--frames", "1"});
  EXPECT_EQ(r.exit_status, 2);
  EXPECT_NE(r.err.find("already holds a frame directory"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir.file("000000.pgm")));

  r = test::run_process({kTool, "synth", config, "--out", dir.file("y"), "--lanes", "2", "--lane-change-at", "1"});
  EXPECT_EQ(r.exit_status, 2);
  EXPECT_EQ(r.err, "ccdlane: --lane-change-at: the vehicle is in the rightmost lane; there is no lane to change to\n");
  EXPECT_FALSE(std::filesystem::exists(dir.file("y")));

  r = test::run_process({kTool, "synth", config});
  EXPECT_EQ(r.exit_status, 2);
  EXPECT_NE(r.err.find("--out"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace ccdlane

namespace ccdlane {
namespace {

// A configuration within the limits that still needs more memory than the process may
// have (ulimit -v): one plain line, exit 1, never "std::bad_alloc".
TEST(SynthCommand, OutOfMemoryIsOneLineNotARawBadAlloc) {
  test::TempDir dir;
  const std::string config =
      dir.write("big.toml", "[camera]\nNu = 8192\nNv = 8192\nUc_mm = 0.0007\nVc_mm = 0.0005\nk_px2 = 0\n");
  const auto r = test::run_process({"/bin/sh", "-c", "ulimit -v 300000; exec \"$@\"", "sh", CCDLANE_TOOL, "synth",
                                    config, "--out", dir.file("out"), "--frames", "1"});
  EXPECT_EQ(r.exit_status, 1) << r.err;
  EXPECT_EQ(r.err, "ccdlane: out of memory: the configuration or input asks for more than this machine has\n");
}

}  // namespace
}  // namespace ccdlane
