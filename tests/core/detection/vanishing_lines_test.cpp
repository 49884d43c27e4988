// The vanishing point from lines of bars: bars drawn along lines through a known point
// among clutter; the bars the detector finds in a rendered highway whose pose is known,
// with the nominal mount off by 5 degrees; and no point where no lines meet.
#include "core/detection/vanishing_lines.hpp"

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "core/detection/ground_projector.hpp"
#include "core/detection/lane_detector.hpp"
#include "tests/core/synth/rendered_road.hpp"
#include "tests/support/allocation_counter.hpp"

namespace ccdlane {
namespace {

MarkCandidate bar(double x, double y, double contrast = 40.0) {
  MarkCandidate m;
  m.left_px = x - 2.0;
  m.right_px = x + 2.0;
  m.py = y;
  m.contrast = contrast;
  return m;
}

// A camera with no distortion, so that drawn pixels are ideal ones.
CameraSpec plain_camera() {
  CameraSpec c = default_config().camera;
  c.k_px2 = 0.0;
  return c;
}

// The plain camera at the default mount, and where the straight road's lines meet in its
// pictures.
struct PlainView {
  CameraSpec camera = plain_camera();
  CameraPose nominal = default_config().nominal_pose();
  double vx = 0.0, vy = 0.0;
  bool has_point = GroundProjector(camera, nominal).vanishing_point(0.0, vx, vy);
};

// Four lane lines through (vx, vy) seen from row 300 down, as dashes (bars on every
// second row of one dash in three), with 0.3 px of noise, among 400 bars of clutter.
std::vector<MarkCandidate> lines_and_clutter(double vx, double vy, int Nu, int Nv, std::mt19937& rng) {
  std::vector<MarkCandidate> bars;
  std::normal_distribution<double> noise(0.0, 0.3);
  for (const double slope : {-1.6, -0.6, 0.6, 1.6})
    for (int y = 300; y < Nv; y += 2)
      if ((y / 30) % 3 == 0) bars.push_back(bar(vx + slope * (y - vy) + noise(rng), y));
  std::uniform_real_distribution<double> x(0, Nu), y(vy + 10, Nv);
  for (int i = 0; i < 400; ++i) bars.push_back(bar(x(rng), y(rng)));
  return bars;
}

TEST(VanishingLineFinder, TheLinesOfBarsCrossWhereTheyWereDrawn) {
  const PlainView view;
  ASSERT_TRUE(view.has_point);
  const auto& [camera, nominal, vx, vy, has_point] = view;
  VanishingLineFinder finder(camera, 4096);
  std::mt19937 rng(3);
  for (const double dx : {-40.0, 0.0, 60.0}) {
    const std::vector<MarkCandidate> bars = lines_and_clutter(vx + dx, vy - 30.0, camera.Nu, camera.Nv, rng);
    finder.clear();
    finder.add(bars);
    const VanishingPoint& vp = finder.find(nominal);
    ASSERT_TRUE(vp.found) << dx;
    // Lines of 0.3 px noise over 150 rows and more: their crossing to a fraction of a pixel.
    EXPECT_NEAR(vp.x, vx + dx, 0.5) << dx;
    EXPECT_NEAR(vp.y, vy - 30.0, 0.5) << dx;
    EXPECT_GE(finder.lines().size(), 4u);
  }
}

// Two long lines of bars that cross on the road, below the horizon, with most of their
// rows above the crossing (a car's edge, a pole, a roadside's line: TuSimple still 36 seen
// from a mount 5 degrees off made such a point 180 rows below the horizon): no point, as
// a road line's marks lie below its vanishing point. The same lines crossing above their
// bars are one.
TEST(VanishingLineFinder, LinesRunningOnFarAboveTheirCrossingMakeNoPoint) {
  const PlainView view;
  ASSERT_TRUE(view.has_point);
  const auto& [camera, nominal, vx, vy, has_point] = view;
  VanishingLineFinder finder(camera, 4096);
  const auto crossing_lines = [&](double cx, double cy, int rows_above, int rows_below) {
    std::vector<MarkCandidate> bars;
    for (const double slope : {-0.6, 0.9})
      for (int y = static_cast<int>(cy) - rows_above; y <= static_cast<int>(cy) + rows_below; y += 2)
        bars.push_back(bar(cx + slope * (y - cy), y));
    return bars;
  };
  const std::vector<MarkCandidate> on_the_road = crossing_lines(vx - 60.0, vy + 80.0, 160, 60);
  finder.add(on_the_road);
  EXPECT_FALSE(finder.find(nominal).found);
  const std::vector<MarkCandidate> below_it = crossing_lines(vx - 60.0, vy + 80.0, 0, 220);
  finder.clear();
  finder.add(below_it);
  const VanishingPoint& vp = finder.find(nominal);
  ASSERT_TRUE(vp.found);
  EXPECT_NEAR(vp.x, vx - 60.0, 1.0);
  EXPECT_NEAR(vp.y, vy + 80.0, 1.0);
}

// Paint on a road in a third of daylight stands a third as far above it, and the
// row's contrast threshold is a third of daylight's (contrast_threshold.hpp). Weighed
// in grey levels, a dim road's lines fell short of a line's votes while a car's lit
// edge did not (a TuSimple still at a third of its light took a car's edge for a lane
// line). Weighed in units of their rows' light, they count as in daylight.
TEST(VanishingLineFinder, ADimRoadsLinesCountAsInDaylight) {
  const PlainView view;
  ASSERT_TRUE(view.has_point);
  const auto& [camera, nominal, vx, vy, has_point] = view;
  VanishingLineFinder finder(camera, 4096);
  constexpr double kShare = 0.3;
  const auto two_short_lines = [&](double contrast) {
    std::vector<MarkCandidate> bars;
    for (const double slope : {-1.2, 1.2})
      for (int k = 0; k < 8; ++k) {  // 8 bars over 56 rows: a line's fewest bars and rows, and some
        const double y = vy + 120.0 + 8.0 * k;
        bars.push_back(bar(vx + slope * (y - vy), y, contrast));
        bars.back().scan_row = static_cast<std::int16_t>(bars.size() - 1);
      }
    return bars;
  };
  const std::vector<MarkCandidate> daylight = two_short_lines(40.0), dim = two_short_lines(40.0 * kShare);
  const std::vector<float> dim_rows(dim.size(), static_cast<float>(kShare));
  finder.add(daylight);
  const VanishingPoint in_daylight = finder.find(nominal);
  ASSERT_TRUE(in_daylight.found);
  EXPECT_NEAR(in_daylight.x, vx, 0.5);
  EXPECT_NEAR(in_daylight.y, vy, 0.5);
  finder.clear();
  finder.add(dim);
  EXPECT_FALSE(finder.find(nominal).found) << "as grey levels, the dim lines are too faint";
  finder.clear();
  finder.add(dim, dim_rows);
  const VanishingPoint& in_dim_light = finder.find(nominal);
  ASSERT_TRUE(in_dim_light.found);
  EXPECT_NEAR(in_dim_light.x, in_daylight.x, 1e-6);
  EXPECT_NEAR(in_dim_light.y, in_daylight.y, 1e-6);
  EXPECT_NEAR(in_dim_light.strength, in_daylight.strength, 1e-6);
}

// The same road seen by a camera of 1.5 times the pixels (the same chip and lens, cells a
// third smaller): two lane lines meeting at the road's point, and a short row of bars
// over 27 rows (40.5 at 1.5 times: a car's edge, 41 rows long in TuSimple still 53
// scaled so, took its share of the point and moved it 40 px). A line of bars spans at
// least an angle of view, so the short row is no line at either size; counted in
// pixels, it was one at 1.5 times.
TEST(VanishingLineFinder, ALineSpansTheSameAngleOfViewInACameraOfMorePixels) {
  CameraSpec camera = plain_camera();  // TuSimple's 1280x720, whose focal length the rules were set at
  camera.U_mm = 5.12, camera.V_mm = 2.88, camera.Uc_mm = camera.Vc_mm = 0.004;
  camera.Nu = 1280, camera.Nv = 720, camera.cx = 640.5, camera.cy = 360.5;
  CameraPose nominal = default_config().nominal_pose();
  nominal.f_mm = 4.618;
  double vx = 0, vy = 0;
  ASSERT_TRUE(GroundProjector(camera, nominal).vanishing_point(0.0, vx, vy));
  for (const double scale : {1.0, 1.5}) {
    CameraSpec scaled = camera;
    scaled.Nu = static_cast<int>(std::lround(camera.Nu * scale));
    scaled.Nv = static_cast<int>(std::lround(camera.Nv * scale));
    scaled.Uc_mm = scaled.Vc_mm = camera.Uc_mm / scale;
    scaled.cx = CameraSpec::default_cx(scaled.Nu);
    scaled.cy = CameraSpec::default_cy(scaled.Nv);
    const auto at = [&](double x, double y, double contrast) {
      return bar(scaled.cx + scale * (x - camera.cx), scaled.cy + scale * (y - camera.cy), contrast);
    };
    std::vector<MarkCandidate> bars;
    for (int y = static_cast<int>(vy) + 60; y < camera.Nv; y += 6) {
      bars.push_back(at(vx - 1.2 * (y - vy), y, 40.0));
      bars.push_back(at(vx + 1.2 * (y - vy), y, 40.0));
    }
    for (int k = 0; k < 10; ++k) {  // the short row, leaning right, 150 px left of the right line
      const double y = vy + 200.0 + 3.0 * k;
      bars.push_back(at(vx - 150.0 + 0.9 * (y - vy), y, 20.0));
    }
    VanishingLineFinder finder(scaled, 4096);
    finder.add(bars);
    const VanishingPoint& vp = finder.find(nominal);
    ASSERT_TRUE(vp.found) << scale;
    EXPECT_EQ(finder.lines().size(), 2u) << scale;
    EXPECT_NEAR(vp.x, scaled.cx + scale * (vx - camera.cx), 0.5 * scale) << scale;
    EXPECT_NEAR(vp.y, scaled.cy + scale * (vy - camera.cy), 0.5 * scale) << scale;
  }
}

TEST(VanishingLineFinder, ClutterAloneMakesNoPointAndFindingAllocatesNothing) {
  const CameraSpec camera = plain_camera();
  const CameraPose nominal = default_config().nominal_pose();
  VanishingLineFinder finder(camera, 4096);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> x(0, camera.Nu), y(0.4 * camera.Nv, camera.Nv);
  std::vector<MarkCandidate> bars;
  for (int i = 0; i < 1500; ++i) bars.push_back(bar(x(rng), y(rng)));
  test::AllocationScope scope;
  int found = 0;
  for (int k = 0; k < 10; ++k) {
    finder.clear();
    finder.add({bars.data() + 100 * k, 500});
    found += finder.find(nominal).found;
  }
  EXPECT_EQ(found, 0);
  EXPECT_EQ(scope.count(), 0u);
}

// A straight highway rendered at a known pose; the finder gets the bars the detector
// finds on the rows of the searched range at the nominal mount and at the mount pitched
// down by a search's expected error, as the estimator's search does, with the nominal
// mount off by 5 degrees either way in pitch and yaw. The point is the road direction's
// within half a degree (the edge vote's bound is a degree; measured: sub-pixel but for
// one frame from a mount off in both, 0.37 degrees, where the nominal's rows reach the
// far road's clutter).
TEST(VanishingLineFinder, FindsTheRoadsDirectionInARenderedHighwayWhateverTheNominalMount) {
  Config c = default_config();
  c.attitude = {0.0, 3.0, 0.0};
  c.synth.curvature_per_mm = 0.0;
  test::RenderedRoad road(c);
  LaneDetector detector(c.camera, c.detection);
  // The region LaneEstimator's search gives it: 15 degrees either side of the mount.
  VanishingLineFinder finder(c.camera, 2 * detector.max_candidates(), VanishingPointSearch{15.0, 15.0});
  const double f_px = c.nominal_pose().f_mm / c.camera.pitch_u();
  const double tolerance_px = f_px * std::tan(deg_to_rad(0.5));
  for (const double dtheta : {0.0, 5.0, -5.0})
    for (const double dpsi : {0.0, 5.0, -5.0})
      for (const std::uint64_t k : {0u, 21u, 60u}) {
        const SynthFrame f = road.render(k);
        CameraPose nominal = c.nominal_pose();
        nominal.attitude.theta += deg_to_rad(dtheta);
        nominal.attitude.psi += deg_to_rad(dpsi);
        finder.clear();
        CameraPose down = nominal;
        for (const double pitch : {0.0, kSearchPitchErrorDeg}) {  // as LaneEstimator's search
          if (pitch != 0.0 && finder.find(nominal).found) break;
          down.attitude.theta = nominal.attitude.theta + deg_to_rad(pitch);
          finder.add(detector.bars(road.view, down));
        }
        const VanishingPoint& vp = finder.find(nominal);
        ASSERT_TRUE(vp.found) << "frame " << k << " mount off " << dtheta << "/" << dpsi;
        double tx = 0, ty = 0;
        ASSERT_TRUE(GroundProjector(c.camera, f.pose).vanishing_point(0.0, tx, ty));
        EXPECT_LT(std::hypot(vp.x - tx, vp.y - ty), tolerance_px)
            << "frame " << k << " mount off " << dtheta << "/" << dpsi;
      }
}

}  // namespace
}  // namespace ccdlane
