// `ccdlane calibrate mount` as a user runs it: a drive rendered by `ccdlane synth` with
// the true mount (yaw +1.5, pitch -2, roll +0.5 degrees, H 10 % high), calibrated with
// the nominal one; the tables it writes load as a configuration and lie within 3 of
// their sigmas of the truth; a drive on a bend is refused and nothing is written.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include <gtest/gtest.h>

#include "app/config_loader.hpp"
#include "tests/support/run_process.hpp"

namespace ccdlane {
namespace {

using test::run_process;
using test::TempDir;

// The half-resolution reference camera at 10 frames a second.
std::string config_text(double psi, double theta, double phi, double H, double curvature) {
  std::ostringstream t;
  t << "[camera]\nNu = 400\nNv = 300\nUc_mm = 0.0084\nVc_mm = 0.0084\ncx = 200.5\ncy = 150.5\nk_px2 = "
    << -8.3042e-7 * 4 << "\n[mount]\nH_mm = " << H << "\n[attitude]\npsi_deg = " << psi << "\ntheta_deg = " << theta
    << "\nphi_deg = " << phi
    << "\n[detection]\nmax_picks = 160\n[synth]\nrate_hz = 10.0\ncurvature_per_mm = " << curvature << "\n";
  return t.str();
}

double sigma_of(const std::string& table, const std::string& key) {
  std::smatch m;
  const std::regex pattern("\n" + key + " = [^ ]+  # sigma ([0-9.eE+-]+)");
  if (!std::regex_search(table, m, pattern)) return std::nan("");
  return std::stod(m[1]);
}

std::string read_file(const std::string& path) {
  std::ifstream in(path);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(CalibrateMount, RecoversTheMountOfASynthesisedDriveWithin3Sigma) {
  TempDir dir;
  const std::string truth = dir.write("truth.toml", config_text(1.5, 3.0, 0.5, 1540.0, 0.0));
  const std::string nominal = dir.write("nominal.toml", config_text(0.0, 5.0, 0.0, 1400.0, 0.0));
  const std::string frames = dir.path() + "/drive";
  const auto synth = run_process({CCDLANE_TOOL, "synth", truth, "--out", frames, "--frames", "120"});
  ASSERT_EQ(synth.exit_status, 0) << synth.err;

  const std::string out = dir.path() + "/mount.toml";
  const auto r = run_process({CCDLANE_TOOL, "calibrate", "mount", nominal, frames, "--out", out});
  ASSERT_EQ(r.exit_status, 0) << r.err;
  std::cout << r.err;
  const std::string tables = read_file(out);
  std::cout << tables;
  // The tables load as a configuration (the keys are the loader's).
  const Config got = parse_config(tables, "mount.toml");
  EXPECT_NEAR(got.attitude.psi_deg, 1.5, 3 * sigma_of(tables, "psi_deg"));
  EXPECT_NEAR(got.attitude.theta_deg, 3.0, 3 * sigma_of(tables, "theta_deg"));
  EXPECT_NEAR(got.attitude.phi_deg, 0.5, 3 * sigma_of(tables, "phi_deg"));
  EXPECT_NEAR(got.H_mm, 1540.0, 3 * sigma_of(tables, "H_mm"));
}

// --out on a full device, and into a file the disk has no room for (a file size limit
// of 0): exit 1 with the reason, and no file, whole or partial, left behind.
TEST(CalibrateMount, AnOutThatCannotBeWrittenIsExitOneAndLeavesNoFile) {
  TempDir dir;
  const std::string truth = dir.write("truth.toml", config_text(1.5, 3.0, 0.5, 1540.0, 0.0));
  const std::string nominal = dir.write("nominal.toml", config_text(0.0, 5.0, 0.0, 1400.0, 0.0));
  const std::string frames = dir.path() + "/drive";
  ASSERT_EQ(run_process({CCDLANE_TOOL, "synth", truth, "--out", frames, "--frames", "120"}).exit_status, 0);

  const auto full = run_process({CCDLANE_TOOL, "calibrate", "mount", nominal, frames, "--out", "/dev/full"});
  EXPECT_EQ(full.exit_status, 1) << full.err;
  EXPECT_NE(full.err.find("/dev/full: cannot write: No space left on device"), std::string::npos) << full.err;

  const std::string out = dir.path() + "/mount.toml";
  const auto limited = run_process({"/bin/sh", "-c", "ulimit -f 0; trap '' XFSZ; exec \"$@\"", "sh", CCDLANE_TOOL,
                                    "calibrate", "mount", nominal, frames, "--out", out});
  EXPECT_EQ(limited.exit_status, 1) << limited.err;
  EXPECT_NE(limited.err.find(out + ".tmp."), std::string::npos) << limited.err;
  EXPECT_NE(limited.err.find(": cannot write: File too large"), std::string::npos) << limited.err;
  EXPECT_FALSE(std::filesystem::exists(out));
  for (const auto& e : std::filesystem::directory_iterator(std::filesystem::path(out).parent_path()))
    EXPECT_EQ(e.path().string().find(".tmp."), std::string::npos) << "a temporary left: " << e.path();
}

TEST(CalibrateMount, RefusesADriveOnABendAndWritesNothing) {
  TempDir dir;
  const std::string truth = dir.write("truth.toml", config_text(1.5, 3.0, 0.5, 1540.0, 1.0 / (2 * 400e3)));
  const std::string nominal = dir.write("nominal.toml", config_text(0.0, 5.0, 0.0, 1400.0, 0.0));
  const std::string frames = dir.path() + "/drive";
  ASSERT_EQ(run_process({CCDLANE_TOOL, "synth", truth, "--out", frames, "--frames", "80"}).exit_status, 0);
  const std::string out = dir.path() + "/mount.toml";
  const auto r = run_process({CCDLANE_TOOL, "calibrate", "mount", nominal, frames, "--out", out});
  EXPECT_EQ(r.exit_status, 2);
  EXPECT_NE(r.err.find("only_curves"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("nothing written"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out));
  EXPECT_FALSE(std::filesystem::exists(out + ".tmp"));
}

TEST(CalibrateMount, RefusesARecordingTooShort) {
  TempDir dir;
  const std::string truth = dir.write("truth.toml", config_text(1.5, 3.0, 0.5, 1540.0, 0.0));
  const std::string frames = dir.path() + "/drive";
  ASSERT_EQ(run_process({CCDLANE_TOOL, "synth", truth, "--out", frames, "--frames", "30"}).exit_status, 0);
  const auto r = run_process({CCDLANE_TOOL, "calibrate", "mount", truth, frames});
  EXPECT_EQ(r.exit_status, 2);
  EXPECT_NE(r.err.find("too_short"), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
}

// --lane-width-mm 1e308 once wrote H_mm = inf with exit 0; -5, 0 and NaN were ignored.
TEST(CalibrateMount, ALaneWidthOutside2To5MetresIsRefused) {
  TempDir dir;
  const std::string truth = dir.write("truth.toml", config_text(1.5, 3.0, 0.5, 1540.0, 0.0));
  for (const std::string width : {"1e308", "-5", "0", "nan", "inf", "1999", "5001", "3.6m"}) {
    const auto r = run_process({CCDLANE_TOOL, "calibrate", "mount", truth, dir.path(), "--lane-width-mm", width});
    EXPECT_EQ(r.exit_status, 2) << width << ": " << r.err;
    EXPECT_NE(r.err.find("--lane-width-mm: must be a number from 2000 to 5000, got " + width), std::string::npos)
        << r.err;
  }
}

}  // namespace
}  // namespace ccdlane

namespace ccdlane {
namespace {

// A video is a recording like any other: one of another size than the camera is refused
// naming both, and nothing is written.
TEST(CalibrateMountCommand, AVideoOfAnotherSizeIsRefusedNamingBoth) {
  test::TempDir dir;
  const std::string video = std::string(CCDLANE_TEST_DATA_DIR) + "/real/udacity-drives/project_video_segA.mp4";
  const std::string camera = std::string(CCDLANE_SOURCE_DIR) + "/tools/demo/reference-camera.toml";
  const auto r =
      test::run_process({CCDLANE_TOOL, "calibrate", "mount", camera, video, "--out", dir.file("mount.toml")});
  EXPECT_EQ(r.exit_status, 2);
  EXPECT_EQ(r.err, "ccdlane: " + video + ": frames are 1280x720, the camera of " + camera + " is 800x600\n");
  EXPECT_FALSE(std::filesystem::exists(dir.file("mount.toml")));
}

}  // namespace
}  // namespace ccdlane
