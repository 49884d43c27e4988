// A double line (two stripes of paint side by side: a no-passing line, a carpool lane's
// edge) is one marking, placed at its middle: where a driver sees the line and where lane
// benchmarks label it (TuSimple stills 63 and 70, whose line was the inner stripe, 30-40 px
// from the labels near the car). A stripe beside something that is no second stripe stays
// where it is.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/detection/lane_detector.hpp"
#include "tests/core/detection/marker_drawing.hpp"

namespace ccdlane {
namespace {

using test::draw_band;

constexpr double kLineY = 1800.0;  // the double line's middle
constexpr double kStripeWidthMm = 120.0, kStripeGapMm = 300.0;  // between the stripes' middles
constexpr std::uint8_t kPaintGrey = 230;

struct Road : test::TuSimpleConcreteRoad {
  Road() : TuSimpleConcreteRoad(11) {}
  void stripe(double Y, double width_mm = kStripeWidthMm, double X_near = 4000.0) {
    draw_band(frame.view, ground, model, Y, X_near, 40000.0, width_mm, kPaintGrey);
  }
};

// Where across the road the picks of the one line detection reports lie: their mean, and
// how far the farthest lies from it beyond a pixel at its distance (TuSimple's camera:
// 0.87 mm per pixel per metre ahead), mm.
struct PicksAcross {
  double mean = 1e9, worst = 1e9;
};

PicksAcross picks_across(const Road& road) {
  LaneDetector det(road.c.camera, road.c.detection);
  const DetectionResult& r = det.detect(road.frame.view, road.pose, {});
  EXPECT_EQ(r.num_lines, 1);
  if (r.num_lines != 1) return {};
  const DetectedLine& l = r.lines[0];
  EXPECT_GE(l.num_picks, road.c.detection.min_marks);
  std::vector<Vec2> at;  // X, Y of each pick
  for (int p = l.first_pick; p < l.first_pick + l.num_picks; ++p) {
    double X = 0, Y = 0;
    const Pick& pick = r.picks[static_cast<std::size_t>(p)];
    if (road.ground.ground(pick.px, pick.py, X, Y)) at.emplace_back(X, Y);
  }
  if (at.empty()) return {};
  PicksAcross a{0.0, 0.0};
  for (const Vec2& p : at) a.mean += p.y() / static_cast<double>(at.size());
  for (const Vec2& p : at) a.worst = std::max(a.worst, std::abs(p.y() - a.mean) - p.x() / 1000.0);
  return a;
}

TEST(LaneDetectorDoubleLine, ADoubleLinesPicksAreItsMiddle) {
  Road road;
  road.stripe(kLineY + 0.5 * kStripeGapMm);
  road.stripe(kLineY - 0.5 * kStripeGapMm);
  // Each pick is a bar's middle moved by half the mean gap of many pairs: within a pixel.
  const PicksAcross a = picks_across(road);
  EXPECT_NEAR(a.mean, kLineY, 10.0);
  EXPECT_LT(a.worst, 10.0);
}

TEST(LaneDetectorDoubleLine, AStripeBesideAWideBrightBandStaysWhereItIs) {
  // A pale strip of a shoulder, a kerb's top: bright, and narrow enough for paint, but
  // more than half as wide again as the stripe.
  Road road;
  road.stripe(kLineY);
  road.stripe(kLineY + kStripeGapMm, 280.0);
  // The line is one of them (the wider), where it is, and not between them.
  const PicksAcross a = picks_across(road);
  EXPECT_TRUE(std::abs(a.mean - kLineY) < 10.0 || std::abs(a.mean - kLineY - kStripeGapMm) < 10.0) << a.mean;
}

TEST(LaneDetectorDoubleLine, AStripeWithAShortSecondOneBesideItStaysWhereItIs) {
  // The second stripe only beyond 20 m, beside fewer than half of the line's bars (a
  // merge's start): not a double line.
  Road road;
  road.stripe(kLineY);
  road.stripe(kLineY + kStripeGapMm, kStripeWidthMm, 20000.0);
  const PicksAcross a = picks_across(road);
  EXPECT_NEAR(a.mean, kLineY, 10.0);
  EXPECT_LT(a.worst, 10.0);
}

// A buffer beside a carpool lane (California): two double lines 1.2 m apart, four stripes
// of paint within 1.5 m on every row, as close as a zebra crossing's bars but of a lane
// line's width: no crossing (lane_detector.cpp, kMinCrossingBarMm), and the line found is
// the buffer's. Bars 0.3 m wide (the US's narrowest), 1 m apart, a dash long across the
// road are a crossing: dropped, and no line there.
TEST(LaneDetectorDoubleLine, ABuffersTwoDoubleLinesAreNoCrossing) {
  constexpr double kBufferMm = 1200.0;  // between the inner stripes' middles
  const double outer = kLineY + 2 * kStripeGapMm + kBufferMm;
  Road buffer;
  for (const double Y : {kLineY, kLineY + kStripeGapMm, outer - kStripeGapMm, outer}) buffer.stripe(Y);
  LaneDetector det(buffer.c.camera, buffer.c.detection);
  const DetectionResult& r = det.detect(buffer.frame.view, buffer.pose, {});
  EXPECT_EQ(r.counters.crossing_bars, 0);
  ASSERT_EQ(r.num_lines, 1);
  const double at = r.lines[0].fit.y_at(10000.0);
  EXPECT_TRUE(at > kLineY - 50.0 && at < outer + 50.0) << at;

  Road crossing;
  for (int k = 0; k < 5; ++k)
    draw_band(crossing.frame.view, crossing.ground, crossing.model, -2000.0 + 1000.0 * k, 12000.0, 15000.0, 300.0,
              kPaintGrey);
  const DetectionResult& x = det.detect(crossing.frame.view, crossing.pose, {});
  EXPECT_GT(x.counters.crossing_bars, 20);
  EXPECT_EQ(x.num_lines, 0);
}

}  // namespace
}  // namespace ccdlane
