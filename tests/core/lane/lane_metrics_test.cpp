// Lane width, lateral offset, heading and departure from solved lines, as docs/interfaces.md
// defines them, including the cases without a lane.
#include "core/lane/lane_metrics.hpp"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

namespace ccdlane {
namespace {

std::vector<EstimatedLine> lines(std::initializer_list<double> y0, double m = 0.0) {
  std::vector<EstimatedLine> out;
  for (double y : y0) {
    EstimatedLine l;
    l.y0_mm = y;
    l.m = m;
    out.push_back(l);
  }
  return out;
}

TEST(LaneMetrics, OwnLaneIsBoundedByTheNearestLineOnEachSide) {
  const auto l = lines({5300, 1700, -1900, -5500});
  const LaneMetrics m = lane_metrics(l, 0.0, 0.0, 900);
  ASSERT_TRUE(m.has_lane);
  EXPECT_EQ(m.left, 1);
  EXPECT_EQ(m.right, 2);
  EXPECT_DOUBLE_EQ(m.lane_width_mm, 3600);
  EXPECT_DOUBLE_EQ(m.lateral_offset_mm, 100);  // -(1700 - 1900) / 2: left of the centre
  EXPECT_EQ(m.departure, Departure::none);
}

TEST(LaneMetrics, HeadingIsYawLessMountLessTheLanesSlope) {
  EXPECT_NEAR(lane_metrics(lines({1800, -1800}), 1.5, 0.5, 900).heading_deg, 1.0, 1e-12);
  // A lane running off to the right (m < 0) means the vehicle points left of it.
  EXPECT_NEAR(lane_metrics(lines({1800, -1800}, -0.01), 0.0, 0.0, 900).heading_deg, rad_to_deg(std::atan(0.01)), 1e-12);
}

TEST(LaneMetrics, CurvatureIsTheOwnLanesTwoCPerMetre) {
  auto l = lines({5400, 1800, -1800});
  for (auto& line : l) line.c_per_mm = 2.5e-7;  // R = 1 / (2 c) = 2000 m
  l[0].c_per_mm = 9e-6;                         // not the own lane's: no say
  EXPECT_NEAR(lane_metrics(l, 0, 0, 900).curvature_per_m, 1.0 / 2000.0, 1e-15);
  // With a slope, the curvature of y = y0 + m x + c x^2 at x = 0: 2 c / (1 + m^2)^(3/2).
  auto s = lines({1800, -1800}, 0.2);
  for (auto& line : s) line.c_per_mm = -2.5e-7;
  EXPECT_NEAR(lane_metrics(s, 0, 0, 900).curvature_per_m, -5e-4 / std::pow(1.04, 1.5), 1e-15);
  EXPECT_EQ(lane_metrics(lines({1800, -1800}), 0, 0, 900).curvature_per_m, 0.0);  // straight
}

TEST(LaneMetrics, DepartureWhenALineIsNearerThanTheThreshold) {
  EXPECT_EQ(lane_metrics(lines({800, -2800}), 0, 0, 900).departure, Departure::left);
  EXPECT_EQ(lane_metrics(lines({2800, -850}), 0, 0, 900).departure, Departure::right);
  EXPECT_EQ(lane_metrics(lines({2700, -900}), 0, 0, 900).departure, Departure::none);  // at, not nearer
  // A narrow lane with both lines near: the nearer side.
  EXPECT_EQ(lane_metrics(lines({1250, -1250}), 0, 0, 1300).departure, Departure::left);
  EXPECT_EQ(lane_metrics(lines({1300, -1250}), 0, 0, 1300).departure, Departure::right);
  // Straddling a line: it is the left line of the lane to its right.
  EXPECT_EQ(lane_metrics(lines({5000, 100, -3500}), 0, 0, 900).departure, Departure::left);
}

TEST(LaneMetrics, NoLaneWithoutBothSidesOrWithAnImplausibleWidth) {
  EXPECT_FALSE(lane_metrics(lines({1800, 5400}), 0, 0, 900).has_lane);
  EXPECT_FALSE(lane_metrics(lines({-1800}), 0, 0, 900).has_lane);
  EXPECT_FALSE(lane_metrics(lines({}), 0, 0, 900).has_lane);
  EXPECT_FALSE(lane_metrics(lines({5400, -1800}), 0, 0, 900).has_lane);  // 7.2 m: a line missed
  EXPECT_FALSE(lane_metrics(lines({900, -900}), 0, 0, 900).has_lane);    // 1.8 m: not a lane
  EXPECT_FALSE(lane_metrics(lines({1200, -1200}), 0, 0, 900).has_lane);  // 2.4 m: nor this
  EXPECT_TRUE(lane_metrics(lines({1250, -1250}), 0, 0, 900).has_lane);   // 2.5 m: the narrowest
  EXPECT_EQ(lane_metrics(lines({5400, -1800}), 0, 0, 900).departure, Departure::none);
}

}  // namespace
}  // namespace ccdlane
