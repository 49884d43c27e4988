// The solve-to-measurement mapping on a hand-made solve: values in SI units, the
// covariance carried over term by term (including the lines' correlation), components
// absent when not free or undetermined, agreement with lane_metrics' heading, and no
// allocation.
#include "core/ldw/lane_measurement.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "tests/support/allocation_counter.hpp"

namespace ccdlane::ldw {
namespace {

// A solve of psi, theta, phi and y0, c of three lines (0 left of the lane, 1 and 2 its
// lines), with a known covariance.
SolveResult solve() {
  SolveResult r;
  r.pose.attitude = {0.02, 0.05, 0.001};
  r.num_lines = 3;
  r.lines[0] = {5400.0, 0.0, 1.1e-6};
  r.lines[1] = {1800.0, 0.0, 1.0e-6};
  r.lines[2] = {-1900.0, 0.0, 0.9e-6};
  const ReducedParam params[] = {{FreeParam::psi, -1}, {FreeParam::theta, -1}, {FreeParam::phi, -1}, {FreeParam::y0, 0},
                                 {FreeParam::y0, 1},   {FreeParam::y0, 2},     {FreeParam::c, 1},    {FreeParam::c, 2}};
  r.num_free = 8;
  for (int j = 0; j < 8; ++j) r.free_params[static_cast<std::size_t>(j)] = params[j];
  r.covariance = ReducedMatrix::Zero(8, 8);
  const double sd[] = {1e-3, 8e-4, 8e-3, 40.0, 30.0, 35.0, 6e-8, 7e-8};
  for (int j = 0; j < 8; ++j) r.covariance(j, j) = sd[j] * sd[j];
  r.covariance(4, 5) = r.covariance(5, 4) = 0.85 * 30.0 * 35.0;  // the own lines, correlated
  r.covariance(0, 4) = r.covariance(4, 0) = 0.1 * 1e-3 * 30.0;
  r.covariance(6, 7) = r.covariance(7, 6) = 0.5 * 6e-8 * 7e-8;
  return r;
}

TEST(MeasurementFromSolve, TakesTheOwnLanesLinesInMetresAndTheAnglesAsTheyAre) {
  const LaneMeasurement m = measurement_from_solve(solve(), 1, 2, 0.005, false);
  EXPECT_DOUBLE_EQ(m.value(kLeftLine), 1.8);
  EXPECT_DOUBLE_EQ(m.value(kRightLine), -1.9);
  EXPECT_DOUBLE_EQ(m.value(kMeasuredHeading), 0.02 - 0.005);
  EXPECT_NEAR(m.value(kMeasuredCurvature), 2 * 0.95e-3, 1e-15);  // 2c per metre, the mean of the two
  EXPECT_DOUBLE_EQ(m.value(kMeasuredPitch), 0.05);
  for (int i = 0; i < kMeasuredRoll; ++i) EXPECT_TRUE(m.present[static_cast<std::size_t>(i)]) << i;
  EXPECT_FALSE(m.present[kMeasuredRoll]);  // the gyro's
  EXPECT_TRUE(measurement_from_solve(solve(), 1, 2, 0.005, true).present[kMeasuredRoll]);
}

TEST(MeasurementFromSolve, CarriesTheSolversCovarianceOver) {
  const LaneMeasurement m = measurement_from_solve(solve(), 1, 2, 0.0, true);
  EXPECT_NEAR(m.covariance(kLeftLine, kLeftLine), 0.030 * 0.030, 1e-15);
  EXPECT_NEAR(m.covariance(kRightLine, kRightLine), 0.035 * 0.035, 1e-15);
  EXPECT_NEAR(m.covariance(kLeftLine, kRightLine), 0.85 * 0.030 * 0.035, 1e-15);
  EXPECT_NEAR(m.covariance(kMeasuredHeading, kLeftLine), 0.1 * 1e-3 * 0.030, 1e-15);
  EXPECT_NEAR(m.covariance(kMeasuredHeading, kMeasuredHeading), 1e-6, 1e-18);
  // kappa = (c1 + c2) * 1000: var = 1e6 (var1 + var2 + 2 cov).
  const double var_kappa = 1e6 * (36e-16 + 49e-16 + 2 * 0.5 * 6e-8 * 7e-8);
  EXPECT_NEAR(m.covariance(kMeasuredCurvature, kMeasuredCurvature), var_kappa, 1e-20);
  EXPECT_NEAR(m.covariance(kMeasuredPitch, kMeasuredPitch), 64e-8, 1e-18);
  EXPECT_NEAR(m.covariance(kMeasuredRoll, kMeasuredRoll), 64e-6, 1e-16);
  EXPECT_EQ(m.covariance(kLeftLine, kMeasuredPitch), 0.0);
}

TEST(MeasurementFromSolve, LeavesOutWhatTheSolveDidNotDetermine) {
  SolveResult r = solve();
  r.num_free = 6;  // c fixed: no curvature
  LaneMeasurement m = measurement_from_solve(r, 1, 2, 0.0, true);
  EXPECT_FALSE(m.present[kMeasuredCurvature]);
  EXPECT_TRUE(m.present[kLeftLine]);
  EXPECT_EQ(m.covariance(kMeasuredCurvature, kMeasuredCurvature), 1.0);

  r = solve();
  r.covariance.row(2).setConstant(kUndetermined);  // roll undetermined (no gyro, roll-offset family)
  r.covariance.col(2).setConstant(kUndetermined);
  m = measurement_from_solve(r, 1, 2, 0.0, true);
  EXPECT_FALSE(m.present[kMeasuredRoll]);
  EXPECT_TRUE(m.present[kLeftLine]);
  EXPECT_TRUE(m.present[kMeasuredHeading]);
  EXPECT_TRUE(m.covariance.allFinite());
}

TEST(MeasurementFromSolve, HeadingIncludesTheLinesSlopeAsLaneMetricsDoes) {
  SolveResult r = solve();
  r.lines[1].m = 0.01;
  r.lines[2].m = 0.03;
  r.free_params[6] = {FreeParam::m, 1};
  r.free_params[7] = {FreeParam::m, 2};
  r.covariance(6, 6) = r.covariance(7, 7) = 1e-6;
  r.covariance(6, 7) = r.covariance(7, 6) = 0.0;
  const LaneMeasurement m = measurement_from_solve(r, 1, 2, 0.004, false);
  EXPECT_NEAR(m.value(kMeasuredHeading), 0.02 - 0.004 - std::atan(0.02), 1e-15);
  const double d = 0.5 / (1 + 0.02 * 0.02);
  EXPECT_NEAR(m.covariance(kMeasuredHeading, kMeasuredHeading), 1e-6 + d * d * 2e-6, 1e-15);
  EXPECT_FALSE(m.present[kMeasuredCurvature]);
}

TEST(MeasurementFromSolve, DoesNotAllocate) {
  const SolveResult r = solve();
  test::AllocationScope scope;
  double sum = 0.0;
  for (int i = 0; i < 10; ++i) sum += measurement_from_solve(r, 1, 2, 0.0, i % 2 == 0).value(kLeftLine);
  EXPECT_EQ(scope.count(), 0u);
  EXPECT_NEAR(sum, 18.0, 1e-12);
}

}  // namespace
}  // namespace ccdlane::ldw
