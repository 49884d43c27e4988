// `ccdlane score` as a user runs it: a drive rendered by `ccdlane synth`, replayed, and
// scored against lane masks rendered from the drive's truth (every pixel's ray cast to
// the road through the camera model at the true pose, independent of the projection the
// scorer uses): every lane found, no false line, nearly every point hit. Then masks that
// disagree with what was reported: a lane shifted sideways is missed (and the line on
// the real paint is false), a lane left out of the mask makes its reported line false.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "app/config_loader.hpp"
#include "base/image_buffer.hpp"
#include "core/geometry/camera_model.hpp"
#include "drivers/frames/frame_directory.hpp"
#include "drivers/frames/png.hpp"
#include "drivers/frames/video_writer.hpp"
#include "tests/support/run_process.hpp"

namespace ccdlane {
namespace {

using Json = nlohmann::json;
const std::string kTool = CCDLANE_TOOL;
const std::string kReferenceCamera = std::string(CCDLANE_SOURCE_DIR) + "/tools/demo/reference-camera.toml";

// How a mask departs from the truth.
struct MaskEdit {
  int shifted_line = -1;  // this line drawn 1 m to the left of where it is
  int left_out = -1;      // this line not drawn
};

// Paint 200 mm wide on every true line from 5 m to 35 m ahead, line j at grey level
// 10 (j + 1), as an annotator would mark a lane (continuous across dash gaps).
void render_masks(const std::string& frames, const std::string& masks, const MaskEdit& edit) {
  const Config config = load_config_file(kReferenceCamera);
  FrameDirectory dir(frames);
  std::filesystem::create_directories(masks);
  const int W = config.camera.Nu, H = config.camera.Nv;
  for (std::size_t i = 0; i < dir.size(); ++i) {
    CameraPose pose = config.nominal_pose();
    pose.attitude = {deg_to_rad(*dir.truth(i, "truth_psi_deg")), deg_to_rad(*dir.truth(i, "truth_theta_deg")),
                     deg_to_rad(*dir.truth(i, "truth_phi_deg"))};
    pose.H_mm = *dir.truth(i, "truth_H_mm");
    const CameraModel camera(config.camera, pose);
    const double c = *dir.truth(i, "truth_c_per_mm");
    std::vector<double> y0;
    for (int j = 0; dir.truth(i, "truth_y0_" + std::to_string(j) + "_mm"); ++j)
      y0.push_back(*dir.truth(i, "truth_y0_" + std::to_string(j) + "_mm"));
    std::vector<std::uint8_t> mask(static_cast<std::size_t>(W * H), 0);
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        const auto g = camera.ground_point_from_pixel(Vec2(x + 1, y + 1));
        if (!g || g->x() < 5000.0 || g->x() > 35000.0) continue;
        for (std::size_t j = 0; j < y0.size(); ++j) {
          if (static_cast<int>(j) == edit.left_out) continue;
          const double shift = static_cast<int>(j) == edit.shifted_line ? 1000.0 : 0.0;
          if (std::abs(g->y() - (y0[j] + shift + c * g->x() * g->x())) <= 100.0)
            mask[static_cast<std::size_t>(y * W + x)] = static_cast<std::uint8_t>(10 * (j + 1));
        }
      }
    const std::string stem = std::filesystem::path(dir.row(i).file).stem().string();
    write_png(masks + "/" + stem + ".png", ImageView{mask.data(), W, H, W, PixelFormat::mono8, 8});
  }
}

class ScoreCommand : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir;
    const auto synth = test::run_process(
        {kTool, "synth", kReferenceCamera, "--out", dir_->file("road"), "--frames", "4", "--curvature", "2e-7"});
    ASSERT_EQ(synth.exit_status, 0) << synth.err;
    const auto replay =
        test::run_process({kTool, "replay", kReferenceCamera, dir_->file("road"), "--out", dir_->file("r.jsonl")});
    ASSERT_EQ(replay.exit_status, 0) << replay.err;
  }
  static void TearDownTestSuite() { delete dir_; }

  static Json score(const std::string& masks) {
    const auto r = test::run_process(
        {kTool, "score", kReferenceCamera, dir_->file("road"), dir_->file("r.jsonl"), masks, "--json"});
    EXPECT_EQ(r.exit_status, 0) << r.err;
    std::printf("%s", r.out.c_str());
    return Json::parse(r.out);
  }
  static int lines_reported(int frame) {
    std::ifstream in(dir_->file("r.jsonl"));
    std::string line;
    for (int k = 0; k <= frame; ++k) std::getline(in, line);
    return static_cast<int>(Json::parse(line)["lines"].size());
  }

  static test::TempDir* dir_;
};
test::TempDir* ScoreCommand::dir_ = nullptr;

TEST_F(ScoreCommand, MasksOfTheTruthAreAllFoundWithNoFalseLine) {
  render_masks(dir_->file("road"), dir_->file("truth"), {});
  const Json s = score(dir_->file("truth"));
  ASSERT_EQ(s["frames"].size(), 4u);
  for (const Json& f : s["frames"]) {
    // Every line the drive has in view was reported, and lies on its lane.
    EXPECT_EQ(f["found"], f["lanes"]) << f.dump();
    EXPECT_EQ(f["reported_lines"], f["lanes"]) << f.dump();
    EXPECT_EQ(f["false_lines"], 0) << f.dump();
    EXPECT_GE(f["accuracy"].get<double>(), 0.98) << f.dump();
    EXPECT_EQ(f["reported_lines"].get<int>(), lines_reported(f["frame"].get<int>()));
  }
  EXPECT_GE(s["total"]["lanes"].get<int>(), 4 * 3);
  EXPECT_EQ(s["threshold_px"].get<double>(), 20.0 * 800 / 1280);
  // The text form says the same.
  const auto text = test::run_process(
      {kTool, "score", kReferenceCamera, dir_->file("road"), dir_->file("r.jsonl"), dir_->file("truth")});
  EXPECT_NE(text.out.find("total: 4 frames scored (0 without a mask), threshold 12.5 px: lanes " +
                          std::to_string(s["total"]["found"].get<int>()) + "/" +
                          std::to_string(s["total"]["lanes"].get<int>()) + " found, 0 false lines"),
            std::string::npos)
      << text.out;
}

// The same drive as a lossless MP4 (no gyro: a roll prior instead), replayed and scored:
// frame N's mask is NNNNNN.png, and the lanes are found as from the directory.
TEST_F(ScoreCommand, AVideoIsScoredAgainstMasksNamedByFrameNumber) {
  render_masks(dir_->file("road"), dir_->file("truth-video"), {});
  const std::string video = dir_->file("road.mp4");
  {
    FrameDirectory d(dir_->file("road"));
    const ImageBuffer image(800, 600, PixelFormat::mono8, 8);
    VideoWriter w(video, {.width = 800, .height = 600, .lossless = true});
    for (std::size_t i = 0; i < d.size(); ++i) {
      ASSERT_EQ(d.read(i, image.view()), PgmFault::none);
      w.write(image.view(), d.row(i).t_ns);
    }
    w.finish();
  }
  std::ifstream camera(kReferenceCamera);
  std::ostringstream config_text;
  config_text << camera.rdbuf() << "\n[prior]\nphi_deg = [0.0, 1.0]\n";
  const std::string config = dir_->write("video.toml", config_text.str());
  const auto replay = test::run_process({kTool, "replay", config, video, "--out", dir_->file("rv.jsonl")});
  ASSERT_EQ(replay.exit_status, 0) << replay.err;
  const auto r =
      test::run_process({kTool, "score", config, video, dir_->file("rv.jsonl"), dir_->file("truth-video"), "--json"});
  ASSERT_EQ(r.exit_status, 0) << r.err;
  const Json s = Json::parse(r.out);
  ASSERT_EQ(s["frames"].size(), 4u);
  EXPECT_EQ(s["frames"][1]["file"], "000001");
  EXPECT_EQ(s["total"]["found"], s["total"]["lanes"]) << r.out;
  EXPECT_EQ(s["total"]["false_lines"], 0) << r.out;
}

// Each lane's own result says which one was missed: the shifted one (grey level 20),
// and its points and the frame's add up to the frame's figures.
TEST_F(ScoreCommand, AShiftedLaneIsMissedAndTheLineOnThePaintIsFalse) {
  render_masks(dir_->file("road"), dir_->file("shifted"), {.shifted_line = 1});
  const Json s = score(dir_->file("shifted"));
  for (const Json& f : s["frames"]) {
    EXPECT_EQ(f["found"].get<int>(), f["lanes"].get<int>() - 1) << f.dump();
    EXPECT_EQ(f["false_lines"], 1) << f.dump();
    const Json& lanes = f["lane_results"];
    ASSERT_EQ(lanes.size(), f["lanes"].get<std::size_t>()) << f.dump();
    int found = 0, ego = 0;
    std::size_t points = 0, hit = 0;
    for (const Json& l : lanes) {
      EXPECT_EQ(l["found"].get<bool>(), l["level"].get<int>() != 20) << l.dump();
      found += l["found"].get<bool>();
      ego += l["ego"].get<bool>();
      points += l["points"].get<std::size_t>();
      hit += l["hit_points"].get<std::size_t>();
      EXPECT_EQ(l["missed_rows"].size(), l["points"].get<std::size_t>() - l["hit_points"].get<std::size_t>())
          << l.dump();
      // The line that hits it most, and by how much it passes each point: the points it
      // misses are those it passes farther off than the threshold, or does not reach.
      const Json& offsets = l["offsets_px"];
      ASSERT_EQ(offsets.size(), l["points"].get<std::size_t>()) << l.dump();
      std::size_t off = 0;
      for (const Json& o : offsets) off += o.is_null() || std::abs(o.get<double>()) > s["threshold_px"].get<double>();
      EXPECT_EQ(off, l["missed_rows"].size()) << l.dump();
      if (l["line"].is_null()) {
        EXPECT_EQ(l["hit_points"], 0) << l.dump();
      } else {
        EXPECT_LT(l["line"].get<std::size_t>(), f["line_results"].size()) << l.dump();
      }
      if (l["found"].get<bool>()) {
        EXPECT_FALSE(l["line"].is_null()) << l.dump();
      }
    }
    EXPECT_EQ(found, f["found"].get<int>());
    EXPECT_EQ(ego, f["ego_lanes"].get<int>());
    EXPECT_EQ(points, f["points"].get<std::size_t>());
    EXPECT_EQ(hit, f["hit_points"].get<std::size_t>());
    // Each reported line's own result: the one false line is off its rows, the others on
    // theirs, and they add up to the frame's reported and false lines.
    int reported = 0, false_lines = 0;
    for (const Json& l : f["line_results"]) {
      const auto line_points = l["points"].get<std::size_t>(), on = l["on_lane_points"].get<std::size_t>();
      reported += line_points > 0;
      false_lines += l["false"].get<bool>();
      EXPECT_EQ(l["off_rows"].size(), line_points - on) << l.dump();
      // Replay says where each line's nearest mark is: a row of the picture (600 high).
      ASSERT_TRUE(l["nearest_mark_row"].is_number()) << l.dump();
      EXPECT_GE(l["nearest_mark_row"].get<double>(), 0.5) << l.dump();
      EXPECT_LE(l["nearest_mark_row"].get<double>(), 600.5) << l.dump();
      EXPECT_EQ(l["false"].get<bool>(), static_cast<double>(on) < 0.85 * static_cast<double>(line_points)) << l.dump();
    }
    EXPECT_EQ(reported, f["reported_lines"].get<int>());
    EXPECT_EQ(false_lines, f["false_lines"].get<int>());
  }
}

TEST_F(ScoreCommand, ALineOnNoAnnotatedLaneIsFalse) {
  render_masks(dir_->file("road"), dir_->file("fewer"), {.left_out = 0});
  const Json s = score(dir_->file("fewer"));
  for (const Json& f : s["frames"]) {
    EXPECT_EQ(f["found"], f["lanes"]) << f.dump();
    EXPECT_EQ(f["reported_lines"].get<int>(), f["lanes"].get<int>() + 1) << f.dump();
    EXPECT_EQ(f["false_lines"], 1) << f.dump();
  }
}

TEST_F(ScoreCommand, FramesWithoutAMaskAreNotScoredAndBadMasksAreRefused) {
  render_masks(dir_->file("road"), dir_->file("some"), {});
  std::filesystem::remove(dir_->file("some/000001.png"));
  const Json s = score(dir_->file("some"));
  EXPECT_EQ(s["frames"].size(), 3u);
  EXPECT_EQ(s["total"]["frames_without_mask"], 1);
  // A colour picture is not a mask.
  std::filesystem::create_directories(dir_->file("colour"));
  std::vector<std::uint8_t> rgb(800 * 600 * 3, 7);
  write_png(dir_->file("colour/000000.png"), ImageView{rgb.data(), 800, 600, 2400, PixelFormat::rgb8, 8});
  const auto r = test::run_process(
      {kTool, "score", kReferenceCamera, dir_->file("road"), dir_->file("r.jsonl"), dir_->file("colour")});
  EXPECT_EQ(r.exit_status, 2);
  EXPECT_NE(r.err.find("a lane mask is an 8-bit grey PNG"), std::string::npos) << r.err;
  const auto none = test::run_process(
      {kTool, "score", kReferenceCamera, dir_->file("road"), dir_->file("r.jsonl"), dir_->file("road")});
  EXPECT_EQ(none.exit_status, 2);
  EXPECT_NE(none.err.find("no mask for any frame"), std::string::npos) << none.err;
}

// A replay line whose `lines` holds {} once crashed score (SIGSEGV), and other damage
// gave raw library errors with exit 1: now one line with the file, line and field, exit 2.
TEST_F(ScoreCommand, ADamagedReplayLineIsOneLineNamingFileLineAndField) {
  render_masks(dir_->file("road"), dir_->file("masks"), {});
  std::ifstream in(dir_->file("r.jsonl"));
  std::string first;
  std::getline(in, first);
  const std::pair<std::string, std::string> cases[] = {
      {R"({"frame": 1, "psi_deg": 1, "theta_deg": 1, "phi_deg": 0, "lines": [{}]})",
       ":2: lines[0].y0_mm: not a number"},
      {R"({"frame": "1"})", ":2: frame: not a frame number"},
      {R"({"frame": 1, "psi_deg": 1, "theta_deg": "x"})", ":2: theta_deg: not a number"},
  };
  for (const auto& [bad, why] : cases) {
    const std::string replay = dir_->write("bad.jsonl", first + "\n" + bad + "\n");
    const auto r =
        test::run_process({kTool, "score", kReferenceCamera, dir_->file("road"), replay, dir_->file("masks")});
    EXPECT_EQ(r.exit_status, 2) << bad << ": " << r.err;
    EXPECT_EQ(r.err, "ccdlane: " + replay + why + "\n");
  }
}

// The rings' colours in an overlay: how many pixels are the hit points' green and how
// many the missed points' red.
struct RingPixels {
  int hit = 0, missed = 0;
};
RingPixels ring_pixels(const std::string& png) {
  const OwnedPicture p = read_png_picture(png);
  RingPixels n;
  for (int y = 0; y < p.height; ++y)
    for (int x = 0; x < p.width; ++x) {
      const std::uint8_t* c = p.view().row(y) + 3 * x;
      n.hit += c[0] == 0 && c[1] == 255 && c[2] == 0;
      n.missed += c[0] == 255 && c[1] == 0 && c[2] == 0;
    }
  return n;
}

// --overlay draws each scored frame with every annotated point as a ring, green where a
// line hits it and red where none does: with the truth's masks nearly all green; with
// one of the lanes shifted a metre, that lane's points red (a share of them near the
// share of that lane's points, which the JSON says).
TEST_F(ScoreCommand, OverlaysShowWhichAnnotatedPointsAreHit) {
  render_masks(dir_->file("road"), dir_->file("truth-ov"), {});
  render_masks(dir_->file("road"), dir_->file("shifted-ov"), {.shifted_line = 1});
  for (const char* masks : {"truth-ov", "shifted-ov"}) {
    const std::string out = dir_->file(std::string("overlay-") + masks);
    const auto r = test::run_process({kTool, "score", kReferenceCamera, dir_->file("road"), dir_->file("r.jsonl"),
                                      dir_->file(masks), "--json", "--overlay", out});
    ASSERT_EQ(r.exit_status, 0) << r.err;
    const Json s = Json::parse(r.out);
    ASSERT_EQ(s["frames"].size(), 4u);
    for (const Json& f : s["frames"]) {
      char name[16];
      std::snprintf(name, sizeof name, "/%06d.png", f["frame"].get<int>());
      const RingPixels n = ring_pixels(out + name);
      const double missed_share = 1.0 - f["accuracy"].get<double>();
      const double red_share = static_cast<double>(n.missed) / (n.hit + n.missed);
      // Rings overlap where points lie close (far rows), so pixels are not points:
      // within a tenth of the share.
      EXPECT_NEAR(red_share, missed_share, 0.1) << masks << name << ": " << f.dump();
      EXPECT_GT(n.hit, 0) << masks << name;
    }
  }
  // A video has no frame files to draw on; the overlay may not go inside the frames.
  const auto video = test::run_process({kTool, "score", kReferenceCamera, dir_->file("road.mp4"), dir_->file("r.jsonl"),
                                        dir_->file("truth-ov"), "--overlay", dir_->file("ov-video")});
  EXPECT_EQ(video.exit_status, 2);
  EXPECT_NE(video.err.find("--overlay needs a frame directory"), std::string::npos) << video.err;
  const auto inside = test::run_process({kTool, "score", kReferenceCamera, dir_->file("road"), dir_->file("r.jsonl"),
                                         dir_->file("truth-ov"), "--overlay", dir_->file("road/ov")});
  EXPECT_EQ(inside.exit_status, 2);
  EXPECT_NE(inside.err.find("lies inside the frame directory"), std::string::npos) << inside.err;
}

}  // namespace
}  // namespace ccdlane
