// The radius said to people: a value only under 10 km, "straight" beyond, "-" unsolved.
#include "tools/ccdlane/radius_text.hpp"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

namespace ccdlane::cli {
namespace {

TEST(RadiusText, ARadiusOnlyWhereTheRoadBends) {
  EXPECT_EQ(radius_text(850.4), "850 m");
  EXPECT_EQ(radius_text(-1200.0), "-1200 m");
  EXPECT_EQ(radius_text(9999.0), "9999 m");
  EXPECT_EQ(radius_text(10'000.0), "straight");
  EXPECT_EQ(radius_text(-885'327.0), "straight");  // the straight road
  EXPECT_EQ(radius_text(std::numeric_limits<double>::infinity()), "straight");
  EXPECT_EQ(radius_text(std::nan("")), "-");
}

}  // namespace
}  // namespace ccdlane::cli
