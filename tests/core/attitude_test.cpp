// The attitude matrix: conventions of geometry.md and derivatives.
#include "core/geometry/attitude.hpp"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <gtest/gtest.h>

namespace ccdlane {
namespace {

TEST(Attitude, ZeroLooksAlongTheRoad) {
  const Mat3 t = attitude_matrix({});
  // The optical axis (film z) is fixed x; a picture row (film x) runs along fixed +y;
  // a picture column (film y, down the picture) along fixed +z.
  EXPECT_EQ(t.col(2), Vec3::UnitX());
  EXPECT_EQ(t.col(0), Vec3::UnitY());
  EXPECT_EQ(t.col(1), Vec3::UnitZ());
}

TEST(Attitude, SignConventions) {
  const double a = deg_to_rad(10);
  // Positive yaw turns the view to the left (+y).
  EXPECT_GT(attitude_matrix({a, 0, 0}).col(2).y(), 0.0);
  // Positive pitch tips it down toward the road (-z).
  EXPECT_LT(attitude_matrix({0, a, 0}).col(2).z(), 0.0);
  // Roll is about the viewing direction: the axis stays put.
  EXPECT_LE((attitude_matrix({0, 0, a}).col(2) - Vec3::UnitX()).norm(), 1e-15);
}

TEST(Attitude, IsARotation) {
  const Mat3 t = attitude_matrix({0.3, -0.2, 1.1});
  EXPECT_LE((t * t.transpose() - Mat3::Identity()).norm(), 1e-14);
  EXPECT_NEAR(t.determinant(), 1.0, 1e-14);
}

TEST(Attitude, DerivativesMatchFiniteDifferences) {
  const Attitude a{0.3, -0.2, 1.1};
  Mat3 d[3];
  attitude_matrix(a, &d[0], &d[1], &d[2]);
  const double h = 1e-6;
  for (int k = 0; k < 3; ++k) {
    Attitude p = a, m = a;
    double* pp[] = {&p.psi, &p.theta, &p.phi};
    double* mm[] = {&m.psi, &m.theta, &m.phi};
    *pp[k] += h;
    *mm[k] -= h;
    const Mat3 n = (attitude_matrix(p) - attitude_matrix(m)) / (2 * h);
    EXPECT_LE((n - d[k]).norm(), 1e-9) << "angle " << k;
  }
}

TEST(Attitude, EachAngleTurnsAboutItsAxis) {
  const Attitude a{0.3, -0.2, 1.1};
  Mat3 d[3], axes;
  const Mat3 t = attitude_matrix(a, &d[0], &d[1], &d[2], &axes);
  for (int k = 0; k < 3; ++k) {
    const Vec3 w = axes.col(k);
    EXPECT_NEAR(w.norm(), 1.0, 1e-15) << "angle " << k;
    for (int c = 0; c < 3; ++c) EXPECT_LE((w.cross(t.col(c)) - d[k].col(c)).norm(), 1e-15) << "angle " << k;
  }
}

}  // namespace
}  // namespace ccdlane
