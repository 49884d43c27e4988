// Concrete roads as California's freeways are marked: a few raised markers per line within
// reach, set beside the sealed joint between two slabs. Detection takes the joint for the
// line's course where its markers say it is one, places it where the markers are, and
// never takes a joint alone.
#include <algorithm>
#include <array>
#include <string>

#include <gtest/gtest.h>

#include "app/config_loader.hpp"
#include "core/detection/lane_detector.hpp"
#include "tests/core/detection/marker_drawing.hpp"

namespace ccdlane {
namespace {

using test::concrete;
using test::draw_band;
using test::draw_dot;
using test::draw_sunlit_dot;
using test::Frame;

constexpr double kJointY = -1800.0, kJointWidthMm = 15.0;
constexpr std::uint8_t kJointGrey = 110;  // 40 levels below the concrete's 150
// Three markers, 5-11 m apart, 60 mm beside the joint: too few for a line of their own
// (GroupingParams::min_dots). Square ceramic markers, wider than round ones, sit with
// their centres up to 15 cm off it (TuSimple stills 29, 39, 71).
constexpr std::array<double, 3> kMarkersX = {6000.0, 11000.0, 17000.0};
constexpr double kMarkerOffsetMm = 60.0, kFarMarkerOffsetMm = 140.0;

struct ConcreteRoad {
  Config c = load_config_file(std::string(CCDLANE_TEST_DATA_DIR) + "/real/tusimple/camera.toml");
  CameraPose pose = test::tusimple_pose(c);
  GroundProjector ground{c.camera, pose};
  CameraModel model{c.camera, pose};
  Frame frame{c.camera};

  ConcreteRoad(bool joint, bool markers, double marker_offset_mm = kMarkerOffsetMm) {
    concrete(frame.view, 5);
    if (joint) draw_band(frame.view, ground, model, kJointY, 4000.0, 40000.0, kJointWidthMm, kJointGrey);
    if (markers)
      for (const double X : kMarkersX) draw_dot(frame.view, ground, model, X, kJointY + marker_offset_mm, 230);
  }
};

void check_markers_beside_joint(double offset_mm) {
  ConcreteRoad road(true, true, offset_mm);
  LaneDetector det(road.c.camera, road.c.detection);
  const DetectionResult& r = det.detect(road.frame.view, road.pose, {});
  ASSERT_EQ(r.num_lines, 1) << r.counters.joints << " pieces of joints, " << r.counters.dots << " dots";
  const DetectedLine& l = r.lines[0];
  EXPECT_TRUE(l.dots);
  EXPECT_GE(l.joints, road.c.detection.min_marks);
  // The line is found along the joint: within a pixel and its half width (5 mm per pixel
  // at 5 m, 35 mm at 40 m).
  for (const double X : {5000.0, 20000.0, 35000.0})
    EXPECT_NEAR(l.fit.y_at(X), kJointY, 0.5 * kJointWidthMm + X / 1000.0) << "at " << X << " mm";
  // Its picks are the joint's pieces moved across to the markers beside it: each
  // within its own pixel and the joint's half width, plus the error of the markers' mean
  // offset (each marker placed to a pixel at its distance, three of them).
  double marker_px_mm = 0.0;
  for (const double X : kMarkersX) marker_px_mm += X / 1000.0 / static_cast<double>(kMarkersX.size());
  ASSERT_GE(l.num_picks, road.c.detection.min_marks);
  for (int p = l.first_pick; p < l.first_pick + l.num_picks; ++p) {
    double X = 0, Y = 0;
    ASSERT_TRUE(
        road.ground.ground(r.picks[static_cast<std::size_t>(p)].px, r.picks[static_cast<std::size_t>(p)].py, X, Y));
    EXPECT_NEAR(Y, kJointY + offset_mm, 0.5 * kJointWidthMm + X / 1000.0 + marker_px_mm) << "a pick at " << X << " mm";
  }
}

TEST(LaneDetectorJoints, AFewMarkersBesideAJointAreALineAlongTheJointWhereTheMarkersAre) {
  for (const double offset_mm : {kMarkerOffsetMm, kFarMarkerOffsetMm}) {
    SCOPED_TRACE("markers " + std::to_string(offset_mm) + " mm beside the joint");
    check_markers_beside_joint(offset_mm);
  }
}

// A joint worn or filled beyond 12 m: the markers past its end are the line's evidence
// there. The line reaches them, dot to dot, and they are handed on as picks of their own
// (a row of dots whose picks stopped with its joint was "too_short" beside a full line:
// TuSimple still 81). A marker 10.5 m past the last of them continues nothing.
TEST(LaneDetectorJoints, MarkersBeyondTheJointsEndAreTheLinesPicksThere) {
  ConcreteRoad road(false, false);
  draw_band(road.frame.view, road.ground, road.model, kJointY, 4000.0, 12000.0, kJointWidthMm, kJointGrey);
  for (const double X : {6000.0, 11000.0, 13000.0, 23500.0})
    draw_dot(road.frame.view, road.ground, road.model, X, kJointY + kMarkerOffsetMm, 230);
  LaneDetector det(road.c.camera, road.c.detection);
  const DetectionResult& r = det.detect(road.frame.view, road.pose, {});
  ASSERT_EQ(r.num_lines, 1) << r.counters.joints << " pieces of joints, " << r.counters.dots << " dots";
  const DetectedLine& l = r.lines[0];
  EXPECT_GE(l.joints, road.c.detection.min_marks);
  EXPECT_GT(l.far_mm, 12500.0) << "the line reaches the marker at 13 m";
  EXPECT_LT(l.far_mm, 20000.0) << "and not the one at 23.5 m";
  // Picks beyond the joint's end lie on the markers: within the marker's pixel at its
  // distance and the scatter of a marker's rows about its middle (its chords).
  int beyond = 0;
  for (int p = l.first_pick; p < l.first_pick + l.num_picks; ++p) {
    double X = 0, Y = 0;
    ASSERT_TRUE(
        road.ground.ground(r.picks[static_cast<std::size_t>(p)].px, r.picks[static_cast<std::size_t>(p)].py, X, Y));
    if (X < 12500.0) continue;
    EXPECT_LT(X, 20000.0) << "no pick on the marker at 23.5 m";
    ++beyond;
    EXPECT_NEAR(Y, kJointY + kMarkerOffsetMm, X / 1000.0 + 40.0) << "a pick at " << X << " mm";
  }
  EXPECT_GE(beyond, 1) << "the marker beyond the joint's end";
}

TEST(LaneDetectorJoints, NeitherTheMarkersNorTheJointAloneAreALine) {
  for (const bool joint : {false, true}) {
    ConcreteRoad road(joint, !joint);
    LaneDetector det(road.c.camera, road.c.detection);
    const DetectionResult& r = det.detect(road.frame.view, road.pose, {});
    EXPECT_EQ(r.num_lines, 0) << (joint ? "a seam" : "three markers");
    EXPECT_EQ(r.counters.joints > 0, joint);
  }
}

// In sunlight, a marker the bar pass finds by its lit cap alone is moved a quarter of a
// marker towards its shadow: where the dot pass puts those it finds as cap and shadow
// (the dome's middle). Left where the cap is, they were 25-35 mm off those, on the sun's
// side, and pulled a line of both off its dots.
TEST(LaneDetectorJoints, ASunlitMarkersCapAloneIsTakenForItsDomesMiddle) {
  ConcreteRoad road(false, false);
  for (double X = 5000.0; X < 22000.0; X += 1200.0)
    draw_sunlit_dot(road.frame.view, road.ground, road.model, X, 1800.0, road.pose.H_mm);
  LaneDetector det(road.c.camera, road.c.detection);
  const DetectionResult& r = det.detect(road.frame.view, road.pose, {});
  double caps = 0.0, pairs = 0.0;
  int num_caps = 0, num_pairs = 0;
  for (const MarkCandidate& m : r.marks) {
    if (!m.dot || std::abs(m.Y - 1800.0) > 200.0) continue;
    (m.shadow_side == 0 ? caps : pairs) += m.Y;
    ++(m.shadow_side == 0 ? num_caps : num_pairs);
  }
  ASSERT_GE(num_caps, 3);
  ASSERT_GE(num_pairs, 3);
  EXPECT_NEAR(caps / num_caps, pairs / num_pairs, 12.0);
}

}  // namespace
}  // namespace ccdlane
