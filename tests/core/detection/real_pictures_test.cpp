// Detection and the lane estimate on real colour road pictures (tests/data/real): the
// own lane's lines are found where a person measured the paint (within 3 px), no line
// is reported off the paint, and where the camera's intrinsics are known the lane is
// 3.66 m wide (US highways) within 5 %. Overlays and paint-measure pictures are written
// to <build>/overlays/real-colour/ for a person to look at.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "app/config_loader.hpp"
#include "core/detection/paint_measure.hpp"
#include "core/geometry/camera_model.hpp"
#include "core/lane/lane_estimator.hpp"
#include "tests/support/png_image.hpp"

namespace ccdlane {
namespace {

const std::string kData = std::string(CCDLANE_SOURCE_DIR) + "/tests/data/real/";
const std::string kOverlays = std::string(CCDLANE_BINARY_DIR) + "/overlays/real-colour/";

// One painted line as a person measured it: the centre of the paint (1-based column)
// on 1-based picture rows, chosen where paint is (a dash, not a gap).
struct PaintLine {
  bool own_lane;  // a line of the lane the car is in: it must be found
  std::vector<std::pair<double, double>> row_col;
  // How near a reported line passes each anchor. A line beyond the lane found from a
  // dash or two far away is placed by the road's direction there (line_grouper.hpp,
  // find_lines_beyond), to TuSimple's 20 px rather than to the solve's pixel.
  double tolerance_px = 3.0;
};

struct Picture {
  std::string dir, file;
  std::string config;            // path under the source tree
  bool intrinsics_known;         // lane width in metres is then tested
  std::vector<PaintLine> lines;  // every line detection may report; the own lane's marked
};

// Where the road line y = y0 + m x + c x^2 crosses picture row `py`, or NaN when it
// does not within 2..200 m (bisection on x: the row falls as x grows).
double column_at_row(const CameraModel& cam, const RoadLine& l, double py) {
  auto pixel = [&](double x) { return cam.pixel_from_point(Vec3(x, l.y0_mm + (l.m + l.c_per_mm * x) * x, 0)); };
  double lo = 2000, hi = 200000;
  const auto near = pixel(lo), far = pixel(hi);
  if (!near || !far || (near->y() - py) * (far->y() - py) > 0) return std::nan("");
  for (int i = 0; i < 80; ++i) {
    const double mid = 0.5 * (lo + hi);
    const auto p = pixel(mid);
    if (!p) return std::nan("");
    ((p->y() - py) * (near->y() - py) > 0 ? lo : hi) = mid;
  }
  return pixel(0.5 * (lo + hi))->x();
}

// The picture with detection drawn on it: candidate marks (grey ungrouped, else the
// line's colour), the solved lines (one dot per row) and the measured paint (white).
void write_overlay(const std::string& path, const test::PngImage& frame, const LaneEstimator& est,
                   const CameraModel& cam, const Picture& pic) {
  test::PngImage out = frame;
  const std::uint8_t colours[4][3] = {{255, 40, 40}, {40, 230, 40}, {60, 120, 255}, {255, 0, 255}};
  auto put = [&](int x, int y, const std::uint8_t* rgb) {
    if (x < 0 || y < 0 || x >= out.width || y >= out.height) return;
    std::copy(rgb, rgb + 3, &out.pixels[(static_cast<std::size_t>(y) * out.width + x) * 3]);
  };
  const std::uint8_t grey[3] = {128, 128, 128}, white[3] = {255, 255, 255};
  for (const MarkCandidate& m : est.detection().marks)
    for (int x = static_cast<int>(m.left_px) - 1; x <= static_cast<int>(m.right_px) - 1; ++x)
      put(x, static_cast<int>(m.py) - 1, m.line >= 0 ? colours[m.line % 4] : grey);
  if (!est.solution() || !est.solution()->converged) {  // detection's own fits, at its pose
    const CameraModel at_detection(cam.spec(), est.detection_pose());
    for (int j = 0; j < est.detection().num_lines; ++j) {
      const RoadLine& f = est.detection().lines[static_cast<std::size_t>(j)].fit;
      for (int y = 1; y <= out.height; y += 2) {
        const double x = column_at_row(at_detection, RoadLine{f.y0_mm, f.m, f.c_per_mm}, y);
        if (std::isfinite(x)) put(static_cast<int>(std::lround(x)) - 1, y - 1, colours[j % 4]);
      }
    }
  } else {
    for (int j = 0; j < est.solution()->num_lines; ++j)
      for (int y = 1; y <= out.height; y += 2) {
        const double x = column_at_row(cam, est.solution()->lines[static_cast<std::size_t>(j)], y);
        if (std::isfinite(x)) put(static_cast<int>(std::lround(x)) - 1, y - 1, colours[j % 4]);
      }
  }
  for (const PaintLine& l : pic.lines)
    for (const auto& [row, col] : l.row_col)
      for (int d = -4; d <= 4; ++d) {
        put(static_cast<int>(col) - 1 + d, static_cast<int>(row) - 1, white);
        put(static_cast<int>(col) - 1, static_cast<int>(row) - 1 + d, white);
      }
  test::write_png(path, out.view());
}

void check_picture(const Picture& pic) {
  SCOPED_TRACE(pic.dir + "/" + pic.file);
  const Config config = load_config_file(std::string(CCDLANE_SOURCE_DIR) + "/" + pic.config);
  const test::PngImage frame = test::read_png(kData + pic.dir + "/" + pic.file);
  ASSERT_EQ(frame.format, PixelFormat::rgb8);
  LaneEstimator est(config.estimator_options());
  const LaneEstimate e = est.estimate(frame.view(), 0, 0, std::nullopt);

  std::filesystem::create_directories(kOverlays);
  const std::string stem = kOverlays + pic.dir + "-" + pic.file.substr(0, pic.file.size() - 4);
  test::PngImage measure{std::vector<std::uint8_t>(static_cast<std::size_t>(frame.width) * frame.height), frame.width,
                         frame.height, PixelFormat::mono8};
  render_paint_measure(frame.view(), measure.mutable_view());
  test::write_png(stem + "-measure.png", measure.view());

  const CameraModel cam(config.camera, est.solution() ? est.solution()->pose : est.detection_pose());
  write_overlay(stem + ".png", frame, est, cam, pic);
  const DetectionCounters& n = est.detection().counters;
  std::printf(
      "%s/%s: detection: %d rows, %d candidates, %d off the road, %d wrongly oriented, %d grouped into %d lines\n",
      pic.dir.c_str(), pic.file.c_str(), n.scan_rows, n.candidates, n.off_road, n.wrong_orientation, n.grouped,
      est.detection().num_lines);
  ASSERT_TRUE(e.ok) << "reason " << to_string(e.reason);
  ASSERT_NE(est.solution(), nullptr);
  const SolveResult& s = *est.solution();

  std::printf("%s/%s: %d lines, lane width %.0f mm, offset %.0f mm, heading %.2f deg, theta %.2f deg, rms %.2f px\n",
              pic.dir.c_str(), pic.file.c_str(), s.num_lines, e.lane_width_mm, e.lateral_offset_mm, e.heading_deg,
              e.theta_deg, e.rms_px);
  // Every reported line lies on one measured line (all its measured rows within 3 px, or
  // the line's own tolerance);
  // every own-lane line is among them.
  std::vector<int> found(pic.lines.size(), 0);
  for (int j = 0; j < s.num_lines; ++j) {
    const RoadLine& l = s.lines[static_cast<std::size_t>(j)];
    int on = -1;
    for (std::size_t k = 0; k < pic.lines.size() && on < 0; ++k) {
      bool all = true;
      for (const auto& [row, col] : pic.lines[k].row_col)
        all = all && std::abs(column_at_row(cam, l, row) - col) <= pic.lines[k].tolerance_px;
      if (all) on = static_cast<int>(k);
    }
    std::printf("  line %d: y0 %.0f mm m %.4f c %.2e; at the measured rows:", j, l.y0_mm, l.m, l.c_per_mm);
    for (const PaintLine& p : pic.lines)
      for (const auto& [row, col] : p.row_col) std::printf(" %.1f", column_at_row(cam, l, row) - col);
    if (std::getenv("CCDLANE_PRINT_ROWS"))
      for (double row : {345., 380., 420., 470., 520., 460., 500., 550., 600., 650.})
        std::printf(" [%g: %.1f]", row, column_at_row(cam, l, row));
    std::printf(" -> %s\n", on < 0 ? "OFF THE PAINT" : ("painted line " + std::to_string(on)).c_str());
    EXPECT_GE(on, 0) << "line " << j << " (y0 " << l.y0_mm << " mm) is off the paint";
    if (on >= 0) ++found[static_cast<std::size_t>(on)];
  }
  for (std::size_t k = 0; k < pic.lines.size(); ++k) {
    if (pic.lines[k].own_lane) {
      EXPECT_EQ(found[k], 1) << "own-lane line " << k;
    }
    EXPECT_LE(found[k], 1) << "painted line " << k << " reported twice";
  }
  if (pic.intrinsics_known) {
    EXPECT_NEAR(e.lane_width_mm, 3660.0, 0.05 * 3660.0);
  }
}

const char* const kAdvanced = "tests/tools/data/udacity-advanced.toml";
const char* const kP1 = "tests/core/detection/data/udacity-p1.toml";

// The anchors: centres of the paint (peaks of the paint measure, centre of the part
// above half its height over the road) on rows chosen by eye where a line's paint is,
// read off the pictures; the own lane's lines first, near to far, then the other lines
// detection may report. The yellow line's rows in the first picture are also those of
// the grey-picture test in tests/tools/replay_command_test.cpp.
TEST(RealPictures, UdacityAdvancedStraightLines1) {
  check_picture({"udacity-advanced-colour",
                 "000000.png",
                 kAdvanced,
                 true,
                 {{true, {{650, 309.0}, {550, 455.1}, {460, 584.4}}},   // yellow, solid
                  {true, {{655, 1005.6}, {546, 837.1}, {500, 761.9}}},  // white, dashed
                  {false, {{512, 1043.5}, {500, 988.8}}}}});            // next lane's, dashed
}

TEST(RealPictures, UdacityAdvancedStraightLines2) {
  check_picture({"udacity-advanced-colour",
                 "000001.png",
                 kAdvanced,
                 true,
                 {{true, {{650, 317.6}, {600, 387.1}, {460, 584.5}}},   // white, dashed
                  {true, {{650, 1001.9}, {550, 843.1}, {500, 766.5}}},  // white, solid
                  {false, {{550, 70.6}, {460, 464.4}}}}});              // next lane's, dashed
}

TEST(RealPictures, UdacityP1SolidWhiteCurve) {
  check_picture({"udacity-p1-colour",
                 "000000.png",
                 kP1,
                 false,
                 {{true, {{450, 302.9}, {420, 339.9}, {345, 438.3}}},  // white, dashed
                  {true, {{470, 766.4}, {420, 678.0}, {345, 545.0}}},  // white, solid
                  {false, {{400, 100.0}, {395, 120.4}}}}});            // next lane's, dashed
}

TEST(RealPictures, UdacityP1SolidWhiteRight) {
  check_picture({"udacity-p1-colour",
                 "000001.png",
                 kP1,
                 false,
                 {{true, {{420, 322.9}, {355, 415.3}, {345, 428.5}}},  // white, dashed
                  {true, {{520, 813.3}, {420, 657.0}, {355, 555.5}}},  // white, solid
                  {false, {{380, 168.1}, {350, 300.2}}}}});            // next lane's, dashed
}

// The white line's anchors are on its two dashes in view. Nearer, at row 493, there is no
// paint: the bright flat blob there (columns 778-792, rows 491-496, 16 px by 6 rows) is a
// raised pavement marker (Botts' dot) beside where a dash would be, no bar running towards
// the vanishing point, and the row filter rightly does not take it for paint.
TEST(RealPictures, UdacityP1SolidYellowCurve) {
  check_picture({"udacity-p1-colour",
                 "000002.png",
                 kP1,
                 false,
                 {{true, {{520, 192.1}, {420, 331.2}, {345, 432.6}}},  // yellow, solid
                  {true, {{410, 639.0}, {400, 622.4}, {345, 532.0}}},  // white, dashed
                  {false, {{360, 706.0}, {344, 629.7}}}}});            // next lane's, dashed
}

TEST(RealPictures, UdacityP1SolidYellowCurve2) {
  check_picture({"udacity-p1-colour",
                 "000003.png",
                 kP1,
                 false,
                 {{true, {{520, 197.1}, {420, 331.1}, {345, 433.4}}},   // yellow, solid
                  {true, {{505, 805.1}, {455, 720.5}, {345, 540.0}}},   // white, dashed
                  // next lane's, dashed: found along its length in the picture as a
                  // parallel of the white line (line_in_picture.hpp), it takes that line's
                  // shape 3.6 m across and passes its nearest dash (row 395) 3.6 px off
                  {false, {{395, 892.5}, {368, 757.0}, {343, 641.5}}, 6.0}}});
}

TEST(RealPictures, UdacityP1SolidYellowLeft) {
  check_picture({"udacity-p1-colour",
                 "000004.png",
                 kP1,
                 false,
                 {{true, {{520, 177.4}, {470, 249.9}, {345, 424.5}}},  // yellow, solid
                  {true, {{470, 739.0}, {440, 691.1}, {357, 561.1}}},  // white, dashed
                  {false, {{360, 726.0}, {338, 630.8}}}}});            // next lane's, dashed
}

TEST(RealPictures, UdacityP1WhiteCarLaneSwitch) {
  check_picture({"udacity-p1-colour",
                 "000005.png",
                 kP1,
                 false,
                 {{true, {{520, 212.6}, {420, 342.5}, {380, 395.5}}},  // yellow, solid
                  {true, {{520, 840.8}, {470, 755.6}, {350, 550.0}}},  // white, dashed
                  // next lane's, dashed: found from its far dashes (rows 335-354), it
                  // passes the near one at row 380 10 px off
                  {false, {{380, 799.6}, {345, 635.4}}, 12.0}}});
}

}  // namespace
}  // namespace ccdlane
