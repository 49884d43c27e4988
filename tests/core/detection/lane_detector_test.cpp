// Detection on rendered frames with known truth: every line found and ordered, picks on
// the true lines to a fraction of a pixel, robustness to pose error, the previous frame
// as prior (ids through a lane change), what is not paint rejected, 16-bit frames, and
// no allocation per frame.
#include "core/detection/lane_detector.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "app/config_loader.hpp"
#include "tests/core/detection/detection_truth.hpp"
#include "tests/core/detection/marker_drawing.hpp"
#include "tests/core/synth/rendered_road.hpp"
#include "tests/support/allocation_counter.hpp"

namespace ccdlane {
namespace {

using test::concrete;
using test::draw_dot;
using test::draw_sunlit_dot;
using test::Frame;
using test::kDotRadiusMm;
using test::match;
using test::pick_errors;
using test::PickErrors;

Config highway() {
  Config c = default_config();
  c.attitude = {0.0, 3.0, 0.0};
  return c;
}

TEST(LaneDetector, FindsEveryLineWithSubPixelPicks) {
  test::RenderedRoad road(highway());
  const Config& c = road.config;
  LaneDetector det(c.camera, c.detection);
  double worst_rms = 0;
  for (std::uint64_t k : {0u, 13u, 40u, 77u}) {
    const SynthFrame f = road.render(k);
    const DetectionResult& r = det.detect(road.view, f.pose, {});
    ASSERT_EQ(r.num_lines, 4) << "frame " << k;
    const std::vector<int> truth = match(r, f);
    EXPECT_EQ(truth, (std::vector<int>{0, 1, 2, 3})) << "left to right";
    for (int j = 0; j < 4; ++j) {
      EXPECT_NEAR(r.lines[j].fit.y0_mm, f.y0_mm[j], 60.0) << "frame " << k << " line " << j;
      EXPECT_GT(r.lines[j].num_picks, 15);
      EXPECT_GT(r.lines[j].far_mm - r.lines[j].near_mm, 15000.0);
    }
    EXPECT_LE(static_cast<int>(r.picks.size()), c.detection.max_picks);
    for (std::size_t i = 1; i < r.picks.size(); ++i) EXPECT_GE(r.picks[i].line, r.picks[i - 1].line);
    const PickErrors e = pick_errors(r, f, CameraModel(c.camera, f.pose), truth);
    EXPECT_GT(e.n, 100);
    EXPECT_LT(e.rms, 0.15) << "frame " << k;
    EXPECT_LT(e.worst, 0.8) << "frame " << k;
    worst_rms = std::max(worst_rms, e.rms);
  }
  RecordProperty("worst_pick_rms_px", std::to_string(worst_rms));
}

TEST(LaneDetector, FindsTheLinesFromAWrongPose) {
  Config c = highway();
  c.synth.shadow_depth = 0.3;
  test::RenderedRoad road(c);
  LaneDetector det(c.camera, c.detection);
  const SynthFrame f = road.render(21);
  for (const Attitude err :
       {Attitude{0.02, 0.0, 0.0}, Attitude{0.0, 0.015, 0.0}, Attitude{0.0, -0.015, 0.0}, Attitude{0.0, 0.0, 0.03}}) {
    CameraPose guess = f.pose;
    guess.attitude.psi += err.psi;
    guess.attitude.theta += err.theta;
    guess.attitude.phi += err.phi;
    const DetectionResult& r = det.detect(road.view, guess, {});
    // The own lane's lines at least; picks still on the true lines.
    ASSERT_GE(r.num_lines, 3) << err.psi << " " << err.theta << " " << err.phi;
    const PickErrors e = pick_errors(r, f, CameraModel(c.camera, f.pose), match(r, f));
    EXPECT_LT(e.rms, 0.3);
  }
}

TEST(LaneDetector, TwoToFourLanesCurvesAndDashes) {
  for (int lanes : {2, 3, 4}) {
    Config c = highway();
    c.synth.lanes = lanes;
    c.synth.ego_lane = lanes / 2;
    c.synth.curvature_per_mm = lanes == 3 ? 1.5e-6 : -5e-7;
    c.synth.dashed = lanes == 4 ? DashedLines::all : DashedLines::inner;
    test::RenderedRoad road(c);
    LaneDetector det(c.camera, c.detection);
    const SynthFrame f = road.render(5);
    const DetectionResult& r = det.detect(road.view, f.pose, {});
    // Lines that lie within the picture somewhere between 5 and 40 m.
    const CameraModel cam(c.camera, f.pose);
    int visible = 0;
    for (int j = 0; j < f.num_lines; ++j) {
      const auto a = cam.pixel_from_point(Vec3(15000, f.y0_mm[j] + f.c_per_mm * 15000 * 15000, 0));
      visible += a && a->x() > 0 && a->x() < c.camera.Nu;
    }
    EXPECT_EQ(r.num_lines, std::min(visible, 4)) << lanes << " lanes";
    const PickErrors e = pick_errors(r, f, cam, match(r, f));
    EXPECT_LT(e.rms, 0.2) << lanes << " lanes";
  }
}

TEST(LaneDetector, PriorLinesKeepTheirIdentityThroughALaneChange) {
  Config c = test::small_reference_camera();  // many frames: the half-size camera
  c.synth.lane_change_at_s = 0.5;
  c.synth.lane_change_s = 3.0;
  test::RenderedRoad road(c);
  LaneDetector det(c.camera, c.detection);
  // Follow each road line by the prior chain: road line -> detection index per frame.
  std::vector<RoadLine> priors;
  std::vector<int> road_of;  // road line of each prior
  for (std::uint64_t k = 0; k < 5 * 30; k += 5) {
    const SynthFrame f = road.render(k);
    const DetectionResult& r = det.detect(road.view, f.pose, priors);
    ASSERT_GE(r.num_lines, 2) << "frame " << k;
    const std::vector<int> truth = match(r, f);
    std::vector<int> next_road;
    for (int j = 0; j < r.num_lines; ++j) {
      const int p = r.lines[j].prior_index;
      if (p >= 0) {
        EXPECT_EQ(road_of[static_cast<std::size_t>(p)], truth[static_cast<std::size_t>(j)]) << "frame " << k;
      }
      next_road.push_back(truth[static_cast<std::size_t>(j)]);
    }
    if (k > 0) {
      int continued = 0;
      for (int j = 0; j < r.num_lines; ++j) continued += r.lines[j].prior_index >= 0;
      EXPECT_GE(continued, 2) << "frame " << k;
    }
    priors.clear();
    for (int j = 0; j < r.num_lines; ++j) priors.push_back(r.lines[j].fit);
    road_of = next_road;
  }
  EXPECT_EQ(road.drive.frame(5 * 30).ego_lane, 2);  // the change did happen
}

TEST(LaneDetector, RejectsBarsThatAreNotOnTheRoadOrNotAlongIt) {
  const Config c = highway();
  const CameraPose pose = c.nominal_pose();
  Frame frame(c.camera);
  std::fill(frame.px.begin(), frame.px.end(), 90);
  // A bright bar of mark width crossing the road at 60 degrees to its direction (a
  // shadow's edge, a crossing, a car's trim), and bars in the sky.
  for (int y = 300; y < 600; ++y) {
    const int x = 100 + (y - 300) * 2;
    for (int dx = 0; dx < 4; ++dx) frame.view.row(y)[x + dx] = 220;
  }
  for (int y = 0; y < 250; ++y)
    for (int x = 300; x < 304; ++x) frame.view.row(y)[x] = 220;
  LaneDetector det(c.camera, c.detection);
  const DetectionResult& r = det.detect(frame.view, pose, {});
  EXPECT_EQ(r.num_lines, 0);
  EXPECT_GT(r.counters.wrong_orientation, 50);
  for (const MarkCandidate& m : r.marks) EXPECT_GT(m.py, 270);  // nothing above the horizon
}

// Botts' dots: a road marked only by round raised markers, 10 cm across, in groups of four
// 1.2 m apart with 4.8 m gaps (a Californian pattern), on textured concrete. Each line of
// dots is found where it is, from its dots; the same dots scattered at random make no line.
TEST(LaneDetector, ALineOfBottsDotsIsALine) {
  const Config c = highway();
  const CameraPose pose = c.nominal_pose();
  const GroundProjector ground(c.camera, pose);
  const CameraModel model(c.camera, pose);
  const std::array<double, 2> lines_mm = {1800.0, -1800.0};
  Frame frame(c.camera), scattered(c.camera);
  concrete(frame.view, 7);
  concrete(scattered.view, 7);
  std::uint32_t seed = 11;
  int near_dots = 0;  // where a row spans less road than a dot is long: told from paint
  for (const double Y : lines_mm)
    for (double X0 = 4000.0; X0 < 40000.0; X0 += 8400.0)
      for (int k = 0; k < 4; ++k) {
        draw_dot(frame.view, ground, model, X0 + 1200.0 * k, Y, 230);
        near_dots += X0 + 1200.0 * k <= 20000.0;
        seed = seed * 1664525u + 1013904223u;
        const double X = 4000.0 + (seed >> 8) % 36000, Yr = -6000.0 + static_cast<double>((seed >> 3) % 12000);
        draw_dot(scattered.view, ground, model, X, Yr, 230);
      }
  LaneDetector det(c.camera, c.detection);
  const DetectionResult& r = det.detect(frame.view, pose, {});
  ASSERT_EQ(r.num_lines, 2) << "dots " << r.counters.dots << " of " << r.counters.candidates << " candidates";
  for (int j = 0; j < 2; ++j) {
    const DetectedLine& l = r.lines[static_cast<std::size_t>(j)];
    // Within the dots' radius at the nearest dot and along the range.
    EXPECT_NEAR(l.fit.y_at(5000.0), lines_mm[static_cast<std::size_t>(j)], 50.0) << "line " << j;
    EXPECT_NEAR(l.fit.y_at(20000.0), lines_mm[static_cast<std::size_t>(j)], 50.0) << "line " << j;
    EXPECT_GE(l.num_picks, c.detection.min_marks);
    for (int p = l.first_pick; p < l.first_pick + l.num_picks; ++p) {
      double X = 0, Y = 0;
      ASSERT_TRUE(
          ground.ground(r.picks[static_cast<std::size_t>(p)].px, r.picks[static_cast<std::size_t>(p)].py, X, Y));
      EXPECT_NEAR(Y, lines_mm[static_cast<std::size_t>(j)], 50.0) << "a pick at " << X << " mm";
    }
  }
  EXPECT_GE(r.counters.dots, near_dots / 2);

  LaneDetector det2(c.camera, c.detection);
  EXPECT_EQ(det2.detect(scattered.view, pose, {}).num_lines, 0);
}

// Botts' dots in sunlight, as California's freeways have them: each a lit crescent
// narrower than paint beside its shadow, in the groups of the test above. Found from the
// pairs, where the dots are. Seen by TuSimple's camera (1280x720, 1.69 m up, 7 degrees
// down), where a dot 10 m off spans two rows (from the reference camera's 800x600 at 3
// degrees, one).
TEST(LaneDetector, ALineOfSunlitBottsDotsIsALine) {
  const Config c = load_config_file(std::string(CCDLANE_TEST_DATA_DIR) + "/real/tusimple/camera.toml");
  const CameraPose pose = test::tusimple_pose(c);
  const GroundProjector ground(c.camera, pose);
  const CameraModel model(c.camera, pose);
  const std::array<double, 2> lines_mm = {1800.0, -1800.0};
  Frame frame(c.camera);
  concrete(frame.view, 7);
  for (const double Y : lines_mm)
    for (double X0 = 4000.0; X0 < 40000.0; X0 += 8400.0)
      for (int k = 0; k < 4; ++k) draw_sunlit_dot(frame.view, ground, model, X0 + 1200.0 * k, Y, pose.H_mm);
  LaneDetector det(c.camera, c.detection);
  const DetectionResult& r = det.detect(frame.view, pose, {});
  ASSERT_EQ(r.num_lines, 2) << "dots " << r.counters.dots << " of " << r.counters.candidates << " candidates";
  for (int j = 0; j < 2; ++j) {
    const DetectedLine& l = r.lines[static_cast<std::size_t>(j)];
    EXPECT_TRUE(l.dots);
    EXPECT_NEAR(l.fit.y_at(5000.0), lines_mm[static_cast<std::size_t>(j)], kDotRadiusMm) << "line " << j;
    EXPECT_NEAR(l.fit.y_at(20000.0), lines_mm[static_cast<std::size_t>(j)], kDotRadiusMm) << "line " << j;
    EXPECT_GE(l.num_picks, c.detection.min_marks);
  }
}

TEST(LaneDetector, SixteenBitFramesGiveTheSameLines) {
  test::RenderedRoad road8(highway()), road16(highway(), PixelFormat::mono16, 12);
  const SynthFrame f = road8.render(8);
  road16.render(8);
  LaneDetector det(road8.config.camera, road8.config.detection);
  const DetectionResult r8 = det.detect(road8.view, f.pose, {});
  const DetectionResult& r16 = det.detect(road16.view, f.pose, {});
  ASSERT_EQ(r16.num_lines, r8.num_lines);
  for (int j = 0; j < r8.num_lines; ++j) EXPECT_NEAR(r16.lines[j].fit.y0_mm, r8.lines[j].fit.y0_mm, 20.0);
}

// Dusk, or an underexposed camera: the whole scene a quarter as bright, the paint 8 grey
// levels above the asphalt (below the configured 10) and the sensor clean. Paint's
// contrast falls with the road's light; the threshold follows it (contrast_threshold.hpp).
TEST(LaneDetector, PaintOnADimRoadIsFoundAtTheContrastItHasThere) {
  Config c = highway();
  c.synth.asphalt_grey = 24.0;
  c.synth.texture_grey = 2.5;
  c.synth.paint_grey = 32.0;
  c.synth.sky_grey = 46.0;
  c.synth.verge_grey = 17.0;
  c.synth.noise_sigma = 0.3;
  test::RenderedRoad road(c);
  LaneDetector det(c.camera, c.detection);
  for (std::uint64_t k : {3u, 30u}) {
    const SynthFrame f = road.render(k);
    const DetectionResult& r = det.detect(road.view, f.pose, {});
    ASSERT_EQ(r.num_lines, 4) << "frame " << k;
    EXPECT_EQ(match(r, f), (std::vector<int>{0, 1, 2, 3})) << "frame " << k;
    for (int j = 0; j < 4; ++j) EXPECT_NEAR(r.lines[j].fit.y0_mm, f.y0_mm[j], 60.0) << "frame " << k << " line " << j;
  }
}

TEST(LaneDetector, RowsOfTheHoodAndAboveTheRegionOfInterestAreNotScanned) {
  Config c = highway();
  c.detection.roi_top_px = 320;
  c.detection.hood_px = 100;  // rows 501..600 (1-based) are the hood
  test::RenderedRoad road(c);
  const SynthFrame f = road.render(5);
  LaneDetector det(c.camera, c.detection);
  const DetectionResult& r = det.detect(road.view, f.pose, {});
  ASSERT_GT(r.counters.candidates, 0);
  for (const MarkCandidate& m : r.marks) {
    EXPECT_GT(m.py, 320.0);
    EXPECT_LE(m.py, 600.0 - 100.0);
  }
  EXPECT_GE(r.num_lines, 2) << "the band between still shows the own lane";
}

TEST(LaneDetector, WrongSizedFramesGiveNothingAndDetectionAllocatesNothing) {
  test::RenderedRoad road(highway());
  LaneDetector det(road.config.camera, road.config.detection);
  const SynthFrame f = road.render(2);
  MutableImageView small = road.view;
  small.width = 640;
  EXPECT_EQ(det.detect(small, f.pose, {}).num_lines, 0);
  EXPECT_EQ(det.detect(ImageView{}, f.pose, {}).num_lines, 0);
  const RoadLine priors[] = {{f.y0_mm[1], 0, 0}, {f.y0_mm[2], 0, 0}};
  // Colour too (the paint measure per scanned segment), on a dashed bend (single dashes
  // taken as parallels of the road's lines).
  Config bend = highway();
  bend.synth.colour = true;
  bend.synth.curvature_per_mm = 1.0 / (2.0 * 300e3);
  test::RenderedRoad colour(bend, PixelFormat::rgb8);
  const SynthFrame fc = colour.render(2);
  LaneDetector det_colour(bend.camera, bend.detection);
  const RoadLine bend_priors[] = {{fc.y0_mm[1], 0, fc.c_per_mm}, {fc.y0_mm[2], 0, fc.c_per_mm}};
  test::AllocationScope scope;
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(det.detect(road.view, f.pose, priors).num_lines, 4);
    EXPECT_EQ(det.detect(road.view, f.pose, {}).num_lines, 4);
    EXPECT_GE(det_colour.detect(colour.view, fc.pose, bend_priors).num_lines, 3);
    EXPECT_GE(det_colour.detect(colour.view, fc.pose, {}).num_lines, 3);
  }
  EXPECT_EQ(scope.count(), 0u);
}

}  // namespace
}  // namespace ccdlane
