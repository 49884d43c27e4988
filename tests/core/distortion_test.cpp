// Division-model distortion: closed forms, round trips, rejection, Jacobian.
#include "core/geometry/distortion.hpp"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

namespace ccdlane {
namespace {

const Vec2 kCentre(400.5, 300.5);

TEST(Distortion, ZeroDistortionIsIdentity) {
  const Vec2 p(17.25, 580.5);
  EXPECT_EQ(*undistort_pixel(p, kCentre, 0.0), p);
  EXPECT_EQ(*distort_pixel(p, kCentre, 0.0), p);
}

TEST(Distortion, CentreIsFixed) {
  EXPECT_EQ(*distort_pixel(kCentre, kCentre, -8.3042e-7), kCentre);
  EXPECT_EQ(*undistort_pixel(kCentre, kCentre, 5e-6), kCentre);
}

TEST(Distortion, BarrelPushesIdealPointsOutward) {
  // k < 0: ideal points lie farther from the centre than observed ones (docs/geometry.md).
  const Vec2 observed(20, 30);
  const Vec2 ideal = *undistort_pixel(observed, kCentre, -8.3042e-7);
  EXPECT_GT((ideal - kCentre).norm(), (observed - kCentre).norm());
}

TEST(Distortion, MatchesTheSpecificationsFormOfTheInverse) {
  // r_d = (1 - sqrt(1 - 4 k r_u^2)) / (2 k r_u), written literally.
  for (double k : {-8.3042e-7, -4e-7, 3e-7}) {
    const Vec2 ideal(700.0, 80.0);
    const double ru = (ideal - kCentre).norm();
    const double rd = (1 - std::sqrt(1 - 4 * k * ru * ru)) / (2 * k * ru);
    const Vec2 expected = kCentre + (ideal - kCentre) * (rd / ru);
    EXPECT_LE((*distort_pixel(ideal, kCentre, k) - expected).norm(), 1e-9);
  }
}

TEST(Distortion, RoundTripsWhereverBothAreDefined) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<> coord(-2000, 2000), kd(-3e-6, 3e-6);
  int both = 0;
  for (int i = 0; i < 20000; ++i) {
    const double k = kd(rng);
    const Vec2 ideal = kCentre + Vec2(coord(rng), coord(rng));
    const auto observed = distort_pixel(ideal, kCentre, k);
    if (!observed) {
      EXPECT_GT(k, 0.0) << "barrel distortion is defined everywhere";
      continue;
    }
    const auto back = undistort_pixel(*observed, kCentre, k);
    ASSERT_TRUE(back.has_value());
    EXPECT_LE((*back - ideal).norm(), 1e-9 * (1 + (ideal - kCentre).norm()));
    ++both;
  }
  EXPECT_GT(both, 10000);
}

TEST(Distortion, PincushionRejectsPointsWithNoCounterpart) {
  const double k = 1e-6;
  // 1 + k r^2 <= 0 cannot happen for k > 0, but 4 k r_u^2 > 1 can: r_u > 500 px.
  EXPECT_FALSE(distort_pixel(kCentre + Vec2(501, 0), kCentre, k).has_value());
  EXPECT_FALSE(distort_pixel(kCentre + Vec2(500, 0), kCentre, k).has_value());  // the edge itself
  EXPECT_TRUE(distort_pixel(kCentre + Vec2(499, 0), kCentre, k).has_value());
  // For an observed pixel the bound is 1 + k |d - c|^2 <= 0, i.e. k < 0 and far out.
  EXPECT_FALSE(undistort_pixel(kCentre + Vec2(1001, 0), kCentre, -1e-6).has_value());
  EXPECT_TRUE(undistort_pixel(kCentre + Vec2(999, 0), kCentre, -1e-6).has_value());
}

TEST(Distortion, JacobianMatchesFiniteDifferences) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<> coord(-600, 600), kd(-2e-6, 4e-7);
  for (int i = 0; i < 500; ++i) {
    const double k = kd(rng);
    const Vec2 ideal = kCentre + Vec2(coord(rng), coord(rng));
    Mat2 j;
    if (!distort_pixel(ideal, kCentre, k, &j)) continue;
    Mat2 n;
    const double h = 1e-4;
    for (int c = 0; c < 2; ++c) {
      Vec2 p = ideal, m = ideal;
      p[c] += h;
      m[c] -= h;
      n.col(c) = (*distort_pixel(p, kCentre, k) - *distort_pixel(m, kCentre, k)) / (2 * h);
    }
    EXPECT_LE((j - n).norm(), 1e-7) << j << "\n" << n;
  }
}

TEST(Distortion, TinyRadiiKeepFullPrecision) {
  // Near the centre the spec's quotient form cancels (0/0 in the limit); ours must not.
  // Centre at the origin so that the check sees the formula, not the addition of c.
  const Vec2 origin(0, 0);
  const Vec2 observed = *distort_pixel(Vec2(1e-6, -2e-6), origin, -8.3042e-7);
  EXPECT_NEAR(observed.x(), 1e-6, 1e-21);
  EXPECT_NEAR(observed.y(), -2e-6, 1e-21);
}

}  // namespace
}  // namespace ccdlane
