// Line ids across frames: continued lines keep theirs, missed lines coast with the road
// and keep theirs when found again, new lines get fresh ones, a fresh start restarts at 0.
#include "core/lane/lane_tracker.hpp"

#include <vector>

#include <gtest/gtest.h>

namespace ccdlane {
namespace {

std::vector<int> update(LaneTracker& t, std::initializer_list<double> y0, std::initializer_list<int> prior) {
  std::vector<RoadLine> l;
  for (double y : y0) l.push_back({y, 0, 0});
  std::vector<int> p(prior), ids(l.size());
  t.update(l, p, ids);
  return ids;
}

TEST(LaneTracker, FirstFrameCountsLeftToRightThenIdsStay) {
  LaneTracker t;
  EXPECT_EQ(update(t, {5400, 1800, -1800}, {-1, -1, -1}), (std::vector<int>{0, 1, 2}));
  ASSERT_EQ(t.priors().size(), 3u);
  // Next frame: a new line on the right, the others continued (in detection's order).
  EXPECT_EQ(update(t, {5300, 1700, -1900, -5500}, {0, 1, 2, -1}), (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(update(t, {1600, -2000, -5600}, {1, 2, 3}), (std::vector<int>{1, 2, 3}));
}

// Seen from a height 1.2 times the one they were measured at, the same picture's lines
// lie 1.2 times as far to the side and bend 1.2 times less (y = y0 + m x + c x^2 with x
// and y both scaled); their slopes and ids stay. The point 20 m ahead of the old height's
// line is on the rescaled line 24 m ahead.
TEST(LaneTracker, RescaledLinesAreTheSameRoadSeenFromAnotherHeight) {
  LaneTracker t;
  std::vector<RoadLine> l{{1800.0, 0.01, 2e-7}, {-1800.0, 0.01, 2e-7}};
  std::vector<int> prior{-1, -1}, ids(2);
  t.update(l, prior, ids);
  t.rescale(1.2);
  ASSERT_EQ(t.priors().size(), 2u);
  for (std::size_t j = 0; j < 2; ++j) {
    const RoadLine& r = t.priors()[j];
    EXPECT_NEAR(r.y0_mm, 1.2 * l[j].y0_mm, 1e-9);
    EXPECT_DOUBLE_EQ(r.m, l[j].m);
    EXPECT_NEAR(r.y_at(1.2 * 20000.0), 1.2 * l[j].y_at(20000.0), 1e-6);
  }
  std::vector<int> again(2);
  t.update(l, std::vector<int>{0, 1}, again);
  EXPECT_EQ(again, ids);
}

TEST(LaneTracker, AMissedLineCoastsWithTheRoadAndKeepsItsId) {
  LaneTracker t;
  update(t, {1800, -1800}, {-1, -1});
  // Line 1 missed for a few frames while the road moves 100 mm to the left each frame.
  double y = 1800;
  for (int k = 0; k < 5; ++k) {
    y += 100;
    EXPECT_EQ(update(t, {y}, {0}), std::vector<int>{0});
    ASSERT_EQ(t.priors().size(), 2u);
    EXPECT_NEAR(t.priors()[1].y0_mm, y - 3600, 1e-9);  // predicted with the road's shift
  }
  EXPECT_EQ(update(t, {y + 100, y - 3500}, {0, 1}), (std::vector<int>{0, 1}));
}

TEST(LaneTracker, CoastingEndsAndAFreshStartCountsFromZero) {
  LaneTracker t;
  update(t, {1800, -1800}, {-1, -1});
  for (int k = 0; k < LaneTracker::kCoastFrames; ++k) t.coast();
  EXPECT_EQ(t.priors().size(), 2u);
  t.coast();
  EXPECT_EQ(t.priors().size(), 0u);
  EXPECT_EQ(update(t, {1700, -1900}, {-1, -1}), (std::vector<int>{0, 1}));
  t.reset();
  EXPECT_TRUE(t.priors().empty());
}

TEST(LaneTracker, ANewLineWhereAnEarlierOneShouldBeIsThatLine) {
  LaneTracker t;
  update(t, {1800, -1800}, {-1, -1});
  // The right line is "new" this frame (detection did not continue it) but lies where
  // the earlier one would be: it keeps that id, and is not doubled in the priors.
  EXPECT_EQ(update(t, {1900, -1650}, {0, -1}), (std::vector<int>{0, 1}));
  EXPECT_EQ(t.priors().size(), 2u);
  // Far from any earlier line: a new one.
  EXPECT_EQ(update(t, {1900, -1650, -5300}, {0, 1, -1}), (std::vector<int>{0, 1, 2}));
}

}  // namespace
}  // namespace ccdlane
