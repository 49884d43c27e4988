// The track stage: the solve's lines get the tracker's ids, come out left to right with
// their picks and confidence, and name the own lane's lines in the solve's order.
#include "core/lane/tracked_lines.hpp"

#include <vector>

#include <gtest/gtest.h>

namespace ccdlane {
namespace {

TEST(TrackedLines, OrdersLeftToRightAndNamesTheOwnLaneInTheSolvesOrder) {
  LaneEstimatorOptions o;
  LaneFit fit(o);
  std::vector<Pick> picks;
  DetectionResult d;
  d.num_lines = 3;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 10 + j; ++i) picks.push_back({j, 100.0 + i, 300.0 + i});
  d.picks = picks;
  ASSERT_TRUE(fit.take(d));

  SolveResult r;
  r.num_lines = 3;
  r.lines[0] = {-1800.0, 0.0, 0.0};  // right of the vehicle
  r.lines[1] = {5400.0, 0.0, 0.0};   // two lanes left
  r.lines[2] = {1800.0, 0.0, 0.0};   // left
  LaneTracker tracker;
  const TrackedLines t = track_lines(tracker, r, fit, 0.0, 900.0);
  ASSERT_EQ(t.num_lines, 3);
  EXPECT_EQ(t.lines[0].y0_mm, 5400.0);
  EXPECT_EQ(t.lines[1].y0_mm, 1800.0);
  EXPECT_EQ(t.lines[2].y0_mm, -1800.0);
  EXPECT_EQ(t.lines[0].marks, 11) << "the solve's line 1 had 11 picks";
  EXPECT_DOUBLE_EQ(t.lines[0].confidence, 11.0 / 21.0);
  // A first frame's ids follow the solve's lines (detection hands them left to right);
  // each stays with its line when the lines are ordered.
  EXPECT_EQ(t.lines[0].id, 1);
  EXPECT_EQ(t.lines[1].id, 2);
  EXPECT_EQ(t.lines[2].id, 0);
  ASSERT_TRUE(t.metrics.has_lane);
  EXPECT_EQ(t.own.left, 2);
  EXPECT_EQ(t.own.right, 0);
  EXPECT_DOUBLE_EQ(t.own.lane_width_mm, 3600.0);
}

// Each line's view range is where its own picks lie on the road, whatever order the
// lines come out in; an end pick far from all others does not stretch it.
TEST(TrackedLines, EachLinesViewRangeIsWhereItsPicksLie) {
  LaneEstimatorOptions o;
  LaneFit fit(o);
  std::vector<Pick> picks;
  std::vector<Vec2> points_mm;
  DetectionResult d;
  d.num_lines = 2;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 10; ++i) {
      picks.push_back({j, 100.0 + i, 300.0 + i});
      points_mm.emplace_back(4000.0 * (j + 1) + 2000.0 * i, j == 0 ? -1800.0 : 1800.0);
    }
  picks.push_back({1, 200.0, 250.0});  // line 1's last pick, 40 m beyond its others
  points_mm.emplace_back(8000.0 + 2000.0 * 9 + 40000.0, 1800.0);
  d.picks = picks;
  ASSERT_TRUE(fit.take(d));

  SolveResult r;
  r.num_lines = 2;
  r.lines[0] = {-1800.0, 0.0, 0.0};
  r.lines[1] = {1800.0, 0.0, 0.0};
  r.points_mm = points_mm;
  LaneTracker tracker;
  const TrackedLines t = track_lines(tracker, r, fit, 0.0, 900.0);
  ASSERT_EQ(t.num_lines, 2);
  EXPECT_EQ(t.lines[0].y0_mm, 1800.0);  // the solve's line 1, left
  EXPECT_DOUBLE_EQ(t.lines[0].near_mm, 8000.0);
  EXPECT_DOUBLE_EQ(t.lines[0].far_mm, 26000.0) << "the isolated pick at 66 m is left out";
  EXPECT_DOUBLE_EQ(t.lines[1].near_mm, 4000.0);
  EXPECT_DOUBLE_EQ(t.lines[1].far_mm, 22000.0);
}

}  // namespace
}  // namespace ccdlane
