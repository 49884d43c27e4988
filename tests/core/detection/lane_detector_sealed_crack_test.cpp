// A crack routed and sealed along the lane is two dark beads of sealant with the road's
// own surface between them: a strip a lane mark's width that stands above both its sides,
// as paint does. LaneDetector::between_beads tells it by the road beyond the beads, as
// bright as the strip: without it the strip's bars are kept and make a line.
#include <cmath>

#include <gtest/gtest.h>

#include "core/detection/lane_detector.hpp"
#include "tests/core/detection/marker_drawing.hpp"

namespace ccdlane {
namespace {
// Named apart: the test files of one program are compiled as one (a unity build).
namespace sealed_crack {

using test::draw_band;

constexpr double kLineY = 1800.0;        // a lane line of paint, left of the camera
constexpr double kCrackY = -900.0;       // a sealed crack, right of it
constexpr double kBeadsApartMm = 150.0;  // between the beads' middles
constexpr double kBeadWidthMm = 40.0;
constexpr std::uint8_t kSealant = 40, kPaint = 230;

// The reported line nearest `Y` at 10 m, or nullptr when none is within 300 mm.
const DetectedLine* line_near(const DetectionResult& r, double Y) {
  for (int j = 0; j < r.num_lines; ++j)
    if (std::abs(r.lines[j].fit.y_at(10000.0) - Y) < 300.0) return &r.lines[j];
  return nullptr;
}

TEST(LaneDetectorSealedCrack, TheStripBetweenACracksBeadsIsNoLine) {
  test::TuSimpleConcreteRoad road(5);
  draw_band(road.frame.view, road.ground, road.model, kLineY, 4000.0, 40000.0, 120.0, kPaint);
  for (const double side : {-0.5, 0.5})
    draw_band(road.frame.view, road.ground, road.model, kCrackY + side * kBeadsApartMm, 4000.0, 40000.0, kBeadWidthMm,
              kSealant);
  LaneDetector det(road.c.camera, road.c.detection);
  const DetectionResult& r = det.detect(road.frame.view, road.pose, {});
  EXPECT_NE(line_near(r, kLineY), nullptr) << "the paint's line";
  EXPECT_EQ(line_near(r, kCrackY), nullptr) << "a line on the strip between the beads";
  EXPECT_GT(r.counters.between_beads, 50);
  for (const MarkCandidate& m : r.marks) {
    if (m.joint) continue;
    EXPECT_GT(std::abs(m.Y - kCrackY), 0.5 * kBeadsApartMm) << "a strip's bar at " << m.X << " mm";
  }
}

}  // namespace sealed_crack
}  // namespace
}  // namespace ccdlane
