// The fit stage's own rules: a detection with too few picks is not taken, a detection's
// fixed slopes and curvatures start at 0, and a solve that fits well drops nothing.
#include "core/lane/lane_fit.hpp"

#include <vector>

#include <gtest/gtest.h>

namespace ccdlane {
namespace {

// Two lines of `per_line` picks each, fitted by detection as given.
DetectionResult detection_of(std::vector<Pick>& picks, int per_line) {
  DetectionResult d;
  d.num_lines = 2;
  d.lines[0].fit = {1800.0, 0.01, 1e-6};
  d.lines[1].fit = {-1800.0, 0.01, 1e-6};
  d.lines[1].prior_index = 3;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < per_line; ++i) picks.push_back({j, 100.0 + 10.0 * i, 300.0 + i});
  d.picks = picks;
  return d;
}

TEST(LaneFit, TakesADetectionOnlyWithEnoughPicks) {
  LaneEstimatorOptions o;
  LaneFit fit(o);
  std::vector<Pick> few, enough;
  EXPECT_FALSE(fit.take(detection_of(few, o.detection.min_marks / 2 - 1)));
  const DetectionResult d = detection_of(enough, o.detection.min_marks);
  ASSERT_TRUE(fit.take(d));
  EXPECT_EQ(fit.num_lines(), 2);
  EXPECT_EQ(fit.picks().size(), enough.size());
  EXPECT_EQ(fit.prior_index()[1], 3);
  ASSERT_TRUE(fit.take(d, true));
  EXPECT_EQ(fit.prior_index()[1], -1) << "this frame's own lines continue no previous frame's";
  fit.clear();
  EXPECT_TRUE(fit.picks().empty());
}

TEST(LaneFit, AWellFittingSolveDropsNothing) {
  LaneEstimatorOptions o;
  LaneFit fit(o);
  std::vector<Pick> picks;
  ASSERT_TRUE(fit.take(detection_of(picks, o.detection.min_marks)));
  SolveResult r;
  r.rms_px = o.solver.pixel_sigma;  // within twice the pick noise
  EXPECT_FALSE(fit.drop_outliers(r));
}

}  // namespace
}  // namespace ccdlane
