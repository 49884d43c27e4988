// `ccdlane calibrate camera` as a user runs it: on rendered chessboard pictures of known
// intrinsics (OpenCV must find the corners), on the Udacity pictures against their
// published calibration, and its refusals.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <regex>

#include <gtest/gtest.h>

#include "app/config_loader.hpp"
#include "tests/core/calibration/chessboard_scene.hpp"
#include "tests/support/run_process.hpp"

namespace ccdlane {
namespace {

using calibration::BoardGeometry;
using test::run_process;
using test::TempDir;

const std::string kUdacityDir = std::string(CCDLANE_SOURCE_DIR) + "/tests/data/real/udacity-advanced-chessboard/";
const std::string kUdacityConfig = std::string(CCDLANE_SOURCE_DIR) + "/tests/tools/data/udacity-advanced.toml";

void write_pgm(const std::string& path, const std::vector<std::uint8_t>& grey, int width, int height) {
  std::ofstream out(path, std::ios::binary);
  out << "P5\n" << width << ' ' << height << "\n255\n";
  out.write(reinterpret_cast<const char*>(grey.data()), static_cast<std::streamsize>(grey.size()));
}

// The sigma the tool wrote beside a key of its [camera] table ("f_mm = 2.4  # sigma 0.001").
double sigma_of(const std::string& table, const std::string& key) {
  std::smatch m;
  const std::regex pattern("\n" + key + " = [^ ]+  # sigma ([^\n]+)\n");
  if (!std::regex_search(table, m, pattern)) return std::nan("");
  return std::stod(m[1]);
}

std::string read_file(const std::string& path) {
  std::ifstream in(path);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The rendered camera's chip, with a datasheet-only start: f off by 25 %, centred principal
// point, no distortion.
std::string chessboard_config(const test::ChessboardCamera& c) {
  std::ostringstream t;
  t << "[camera]\nU_mm = " << c.chip.U_mm << "\nV_mm = " << c.chip.V_mm << "\nUc_mm = " << c.chip.Uc_mm
    << "\nVc_mm = " << c.chip.Vc_mm << "\nNu = " << c.chip.Nu << "\nNv = " << c.chip.Nv << "\nf_mm = 3.0\n";
  return t.str();
}

struct RenderedPictures {
  test::ChessboardCamera camera = test::chessboard_camera();
  BoardGeometry board{9, 6, 25.0};
  TempDir dir;
  std::string config = dir.write("camera.toml", chessboard_config(camera));
  std::vector<std::string> pictures;

  RenderedPictures(unsigned seed, int count, double min_tilt_deg = 15.0, double max_tilt_deg = 45.0) {
    std::mt19937 rng(seed);
    const auto poses = test::varied_board_poses(camera, board, count, rng, min_tilt_deg, max_tilt_deg);
    for (std::size_t i = 0; i < poses.size(); ++i) {
      pictures.push_back(dir.file("board" + std::to_string(i) + ".pgm"));
      write_pgm(pictures.back(), test::render_board(camera, board, poses[i], 2.0, rng), camera.chip.Nu, camera.chip.Nv);
    }
  }
  std::vector<std::string> command(std::vector<std::string> extra) const {
    std::vector<std::string> argv{CCDLANE_TOOL, "calibrate", "camera", "--config", config, "--board", "9x6"};
    argv.insert(argv.end(), extra.begin(), extra.end());
    argv.insert(argv.end(), pictures.begin(), pictures.end());
    return argv;
  }
};

TEST(CalibrateCameraCommand, RenderedPicturesGiveTheTruthWithinThreeSigma) {
  RenderedPictures scene(21, 8);
  // A picture without a board: named and skipped, the others go on.
  const std::string blank = scene.dir.file("blank.pgm");
  write_pgm(blank, std::vector<std::uint8_t>(640 * 480, 120), 640, 480);
  scene.pictures.push_back(blank);
  const std::string out = scene.dir.file("calibrated.toml"), overlays = scene.dir.file("overlays");
  const auto r = run_process(scene.command({"--out", out, "--overlay", overlays}));
  ASSERT_EQ(r.exit_status, 0) << r.err;
  EXPECT_NE(r.err.find(blank + ": no 9x6 board found"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("8 of 9 pictures"), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;

  // What it wrote is a configuration the project loads, with the chip unchanged.
  const Config loaded = load_config_file(out);
  EXPECT_EQ(loaded.camera.Nu, 640);
  EXPECT_EQ(loaded.camera.U_mm, scene.camera.chip.U_mm);
  const std::string table = read_file(out);
  const calibration::Intrinsics& t = scene.camera.truth;
  EXPECT_LT(std::abs(loaded.f_mm - t.f_mm), 3.0 * sigma_of(table, "f_mm")) << table;
  EXPECT_LT(std::abs(loaded.camera.cx - t.cx), 3.0 * sigma_of(table, "cx")) << table;
  EXPECT_LT(std::abs(loaded.camera.cy - t.cy), 3.0 * sigma_of(table, "cy")) << table;
  EXPECT_LT(std::abs(loaded.camera.k_px2 - t.k_px2), 3.0 * sigma_of(table, "k_px2")) << table;

  for (int i = 0; i < 8; ++i)
    EXPECT_TRUE(std::filesystem::exists(overlays + "/board" + std::to_string(i) + ".png")) << i;
  EXPECT_FALSE(std::filesystem::exists(overlays + "/blank.png"));
}

TEST(CalibrateCameraCommand, WithoutOutTheTableGoesToStandardOutput) {
  const RenderedPictures scene(22, 4);
  const auto r = run_process(scene.command({}));
  ASSERT_EQ(r.exit_status, 0) << r.err;
  const Config parsed = parse_config(r.out, "stdout");
  EXPECT_NEAR(parsed.f_mm, scene.camera.truth.f_mm, 0.02 * scene.camera.truth.f_mm);
}

// --out on a full device, and into a file the disk has no room for (a file size limit
// of 0: every write to a regular file fails): exit 1 with the reason, and no file, whole
// or partial, left behind.
TEST(CalibrateCameraCommand, AnOutThatCannotBeWrittenIsExitOneAndLeavesNoFile) {
  const RenderedPictures scene(22, 4);
  auto full = run_process(scene.command({"--out", "/dev/full"}));
  EXPECT_EQ(full.exit_status, 1) << full.err;
  EXPECT_NE(full.err.find("/dev/full: cannot write: No space left on device"), std::string::npos) << full.err;

  const std::string out = scene.dir.file("calibrated.toml");
  std::vector<std::string> argv{"/bin/sh", "-c", "ulimit -f 0; trap '' XFSZ; exec \"$@\"", "sh"};
  for (const std::string& a : scene.command({"--out", out})) argv.push_back(a);
  const auto limited = run_process(argv);
  EXPECT_EQ(limited.exit_status, 1) << limited.err;
  EXPECT_NE(limited.err.find(out + ".tmp."), std::string::npos) << limited.err;
  EXPECT_NE(limited.err.find(": cannot write: File too large"), std::string::npos) << limited.err;
  EXPECT_FALSE(std::filesystem::exists(out));
  for (const auto& e : std::filesystem::directory_iterator(std::filesystem::path(out).parent_path()))
    EXPECT_EQ(e.path().string().find(".tmp."), std::string::npos) << "a temporary left: " << e.path();
}

TEST(CalibrateCameraCommand, TwoUsablePicturesAreTooFew) {
  RenderedPictures scene(23, 2);
  const std::string out = scene.dir.file("calibrated.toml");
  const auto r = run_process(scene.command({"--out", out}));
  EXPECT_EQ(r.exit_status, 2);
  EXPECT_NE(r.err.find("2 usable view(s), at least 3 are needed"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out));
}

TEST(CalibrateCameraCommand, BoardsFacingTheCameraAreRefused) {
  RenderedPictures scene(26, 4, 0.0, 2.0);
  const std::string out = scene.dir.file("calibrated.toml");
  const auto r = run_process(scene.command({"--out", out}));
  EXPECT_EQ(r.exit_status, 2);
  EXPECT_NE(r.err.find("the views do not determine f"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("board0.pgm: rms"), std::string::npos) << r.err;  // the pictures are still listed
  EXPECT_FALSE(std::filesystem::exists(out));
}

TEST(CalibrateCameraCommand, PicturesNotOfTheChipSizeAreBadInput) {
  RenderedPictures scene(24, 3);
  const std::string small = scene.dir.file("small.pgm");
  write_pgm(small, std::vector<std::uint8_t>(320 * 240, 120), 320, 240);
  scene.pictures.push_back(small);
  auto r = run_process(scene.command({}));
  EXPECT_EQ(r.exit_status, 2);
  EXPECT_NE(r.err.find(small + ": pictures of different sizes: 320x240"), std::string::npos) << r.err;

  scene.pictures = {small};
  r = run_process(scene.command({}));
  EXPECT_EQ(r.exit_status, 2);
  EXPECT_NE(r.err.find("chip has Nu x Nv = 640x480"), std::string::npos) << r.err;
}

// A chip of Nu = 2 once gave a raw OpenCV assertion: now one line naming the picture.
TEST(CalibrateCameraCommand, APictureTooSmallForTheBoardIsBadInput) {
  const RenderedPictures scene(25, 0);
  const std::string tiny_config = scene.dir.write("tiny.toml", "[camera]\nNu = 2\nNv = 2\n");
  const std::string tiny = scene.dir.file("tiny.pgm");
  write_pgm(tiny, std::vector<std::uint8_t>(4, 120), 2, 2);
  const auto r = run_process({CCDLANE_TOOL, "calibrate", "camera", "--config", tiny_config, "--board", "9x6", tiny});
  EXPECT_EQ(r.exit_status, 2) << r.err;
  EXPECT_EQ(r.err, "ccdlane: " + tiny + ": 2x2 pixels cannot show a 9x6 board (at least 40x28)\n");
}

TEST(CalibrateCameraCommand, BadArgumentsExitTwo) {
  const RenderedPictures scene(25, 0);
  for (const auto& extra :
       std::vector<std::vector<std::string>>{{"--board", "9by6"}, {"--board", "2x6"}, {"--square-mm", "-1"}}) {
    auto argv = scene.command(extra);
    argv.push_back(scene.dir.file("missing.pgm"));
    const auto r = run_process(argv);
    EXPECT_EQ(r.exit_status, 2) << extra[1];
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
  const auto r =
      run_process({CCDLANE_TOOL, "calibrate", "camera", "--config", scene.config, scene.dir.file("missing.pgm")});
  EXPECT_EQ(r.exit_status, 2);
  EXPECT_NE(r.err.find("missing.pgm: cannot open the picture"), std::string::npos) << r.err;
}

std::vector<std::string> udacity_pictures(bool with_odd_sizes) {
  std::vector<std::string> files;
  for (int i = 1; i <= 20; ++i)
    if (with_odd_sizes || (i != 7 && i != 15))
      files.push_back(kUdacityDir + "calibration" + std::to_string(i) + ".jpg");
  return files;
}

// Two of the published pictures are 1281x721, not 1280x720: refused by name.
TEST(CalibrateCameraCommand, UdacityPicturesOfTwoSizesAreRefused) {
  std::vector<std::string> argv{CCDLANE_TOOL, "calibrate", "camera", "--config", kUdacityConfig, "--board", "9x6"};
  for (const std::string& f : udacity_pictures(true)) argv.push_back(f);
  const auto r = run_process(argv);
  EXPECT_EQ(r.exit_status, 2);
  EXPECT_NE(r.err.find("calibration7.jpg: pictures of different sizes: 1281x721"), std::string::npos) << r.err;
}

// The published calibration (tests/data/real/README.md): OpenCV, one radial term, 17
// pictures: fx 1156.7, fy 1151.6, principal point (667.2, 389.0), k1 -0.2546. Here 15
// pictures (7 and 15 have another size; 1, 4 and 5 do not show the whole board).
// Why f differs: the project's model has square cells, one f. OpenCV itself, with fx = fy
// imposed, gives 1163.0 px on the 17 pictures (1164.0 on these 15); the division model
// bends the edge of the field differently from OpenCV's polynomial and adds ~3 px: our fit
// to corners that the published model itself generates (at the fitted board poses) gives
// 1166.3 px. Hence f within 1 % of fx, along a row where f_mm / pitch_u is defined, and
// 1.5 % of fy. k: the division model's k f^2 matches k1 only to first order; on the
// published model's own corners it comes out -0.305, hence 25 % of k1.
TEST(CalibrateCameraCommand, UdacityPicturesAgreeWithThePublishedCalibration) {
  std::vector<std::string> argv{CCDLANE_TOOL, "calibrate", "camera", "--config", kUdacityConfig, "--board", "9x6"};
  for (const std::string& f : udacity_pictures(false)) argv.push_back(f);
  const auto r = run_process(argv);
  ASSERT_EQ(r.exit_status, 0) << r.err;
  for (const char* skipped : {"calibration1.jpg", "calibration4.jpg", "calibration5.jpg"})
    EXPECT_NE(r.err.find(std::string(skipped) + ": no 9x6 board found"), std::string::npos) << skipped;
  EXPECT_NE(r.err.find("15 of 18 pictures"), std::string::npos) << r.err;
  const Config c = parse_config(r.out, "stdout");
  const double f_px = c.f_mm / c.camera.pitch_u();
  EXPECT_LT(std::abs(f_px - 1156.7), 0.01 * 1156.7) << r.err;
  EXPECT_LT(std::abs(f_px - 1151.6), 0.015 * 1151.6) << r.err;
  EXPECT_LT(std::abs(c.camera.cx - 667.2), 5.0) << r.err;
  EXPECT_LT(std::abs(c.camera.cy - 389.0), 5.0) << r.err;
  EXPECT_LT(std::abs(c.camera.k_px2 - -1.91e-7), 0.25 * 1.91e-7) << r.err;
  std::cout << r.err;
}

}  // namespace
}  // namespace ccdlane
