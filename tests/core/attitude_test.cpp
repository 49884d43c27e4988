// The attitude matrix: conventions of docs/geometry.md and derivatives.
#include "core/geometry/attitude.hpp"

#include <cmath>
#include <random>
#include <utility>

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
  const Mat3 t = attitude_matrix(a, &d[0], &d[1], &d[2]);
  EXPECT_EQ(AttitudeTrig::of(a).matrix(&axes), t);
  for (int k = 0; k < 3; ++k) {
    const Vec3 w = axes.col(k);
    EXPECT_NEAR(w.norm(), 1.0, 1e-15) << "angle " << k;
    for (int c = 0; c < 3; ++c) EXPECT_LE((w.cross(t.col(c)) - d[k].col(c)).norm(), 1e-15) << "angle " << k;
  }
}

// A solver's small steps: the trig carried along by the angle-sum formulas stays within a
// few ulp of the trig computed outright, step after step; a large step is computed
// outright.
TEST(Attitude, TrigMovedBySmallStepsStaysExact) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> angle(-0.3, 0.3), step(-AttitudeTrig::kSmallTurn, AttitudeTrig::kSmallTurn);
  for (int walk = 0; walk < 20; ++walk) {
    Attitude a{angle(rng), angle(rng), angle(rng)};
    AttitudeTrig trig = AttitudeTrig::of(a);
    for (int k = 1; k <= 50; ++k) {                   // the solver's default max_iterations
      const double scale = std::pow(10.0, -(k % 8));  // steps from 1e-7 to the largest allowed
      const Attitude next{a.psi + scale * step(rng), a.theta + scale * step(rng), a.phi + scale * step(rng)};
      trig = trig.moved(a, next);
      a = next;
      const AttitudeTrig exact = AttitudeTrig::of(a);
      for (const auto& [carried, direct] : {std::pair{trig.sin_psi, exact.sin_psi},
                                            {trig.cos_psi, exact.cos_psi},
                                            {trig.sin_theta, exact.sin_theta},
                                            {trig.cos_theta, exact.cos_theta},
                                            {trig.sin_phi, exact.sin_phi},
                                            {trig.cos_phi, exact.cos_phi}})
        EXPECT_NEAR(carried, direct, 2e-15) << "walk " << walk << " step " << k;
    }
    EXPECT_LE((trig.matrix() - attitude_matrix(a)).norm(), 4e-15);
  }
  // Beyond kSmallTurn the step is not carried: the result is the outright trig, bit for bit.
  const Attitude from{0.1, 0.2, 0.3}, to{0.1, 0.2 + 2 * AttitudeTrig::kSmallTurn, 0.3};
  const AttitudeTrig far = AttitudeTrig::of(from).moved(from, to);
  EXPECT_EQ(far.sin_theta, AttitudeTrig::of(to).sin_theta);
  EXPECT_EQ(far.cos_theta, AttitudeTrig::of(to).cos_theta);
}

}  // namespace
}  // namespace ccdlane
