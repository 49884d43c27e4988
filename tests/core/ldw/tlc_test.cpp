// Time to line crossing: constant velocity, curvature's acceleration both ways, the
// "not approaching" cases, and that the time found puts the wheel on the line.
#include "core/ldw/tlc.hpp"

#include <gtest/gtest.h>

namespace ccdlane::ldw {
namespace {

TEST(TimeToLineCrossing, AtConstantLateralVelocityIsDistanceOverSpeed) {
  EXPECT_NEAR(*time_to_line_crossing(0.5, 0.5, 0.0), 1.0, 1e-12);
  EXPECT_NEAR(*time_to_line_crossing(0.9, 0.1, 1e-15), 9.0, 1e-9);
}

TEST(TimeToLineCrossing, IsEmptyWhenNotApproaching) {
  EXPECT_FALSE(time_to_line_crossing(0.5, 0.0, 0.0));
  EXPECT_FALSE(time_to_line_crossing(0.5, -0.3, 0.5));  // moving away now: not approaching
  EXPECT_FALSE(time_to_line_crossing(-0.2, -0.3, 0.0));
}

TEST(TimeToLineCrossing, IsZeroOnOrBeyondTheLineWhileApproaching) {
  EXPECT_EQ(*time_to_line_crossing(0.0, 0.2, 0.0), 0.0);
  EXPECT_EQ(*time_to_line_crossing(-0.1, 0.2, 0.0), 0.0);
}

TEST(TimeToLineCrossing, CurvatureTowardTheLineShortensItAndAwayLengthensOrPreventsIt) {
  // 1 = 0.5 t + 0.5 t^2 at t = 1.
  EXPECT_NEAR(*time_to_line_crossing(1.0, 0.5, 1.0), 1.0, 1e-12);
  EXPECT_GT(*time_to_line_crossing(1.0, 0.5, -0.1), 2.0);
  EXPECT_FALSE(time_to_line_crossing(1.0, 0.5, -0.2));  // turns back 0.625 m short of it
}

TEST(TimeToLineCrossing, PutsTheWheelOnTheLine) {
  for (const double d : {0.05, 0.3, 1.2})
    for (const double v : {0.05, 0.4, 1.5})
      for (const double a : {-0.05, 0.0, 0.02, 0.8}) {
        const auto t = time_to_line_crossing(d, v, a);
        if (!t) continue;
        EXPECT_NEAR(v * *t + 0.5 * a * *t * *t, d, 1e-12) << d << " " << v << " " << a;
      }
}

}  // namespace
}  // namespace ccdlane::ldw
