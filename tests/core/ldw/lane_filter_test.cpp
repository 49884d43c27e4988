// The lane filter: initialisation from a solve, the motion model's prediction,
// coasting and losing the track, the Mahalanobis gate, re-association on a lane change,
// restarting after a run of refusals, NEES consistency against a truth that follows the
// filter's own model (chi-square band over Monte Carlo runs), and no allocation.
#include "core/ldw/lane_filter.hpp"

#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Cholesky>
#include <gtest/gtest.h>

#include "core/ldw/chi_square.hpp"
#include "tests/support/allocation_counter.hpp"

namespace ccdlane::ldw {
namespace {

constexpr double kLineSigma = 0.03, kLineCorrelation = 0.8;

// A solve seeing the camera at offset d, heading psi, in a lane of width w.
LaneMeasurement measurement(double d, double psi, double kappa = 0.0, double w = 3.6, double pitch = 0.05) {
  LaneMeasurement m;
  m.value << w / 2 - d, -w / 2 - d, psi, kappa, pitch, 0.0;
  m.covariance.setZero();
  m.covariance(kLeftLine, kLeftLine) = m.covariance(kRightLine, kRightLine) = kLineSigma * kLineSigma;
  m.covariance(kLeftLine, kRightLine) = m.covariance(kRightLine, kLeftLine) =
      kLineCorrelation * kLineSigma * kLineSigma;
  m.covariance(kMeasuredHeading, kMeasuredHeading) = 0.0015 * 0.0015;
  m.covariance(kMeasuredCurvature, kMeasuredCurvature) = 1e-4 * 1e-4;
  m.covariance(kMeasuredPitch, kMeasuredPitch) = 0.001 * 0.001;
  m.covariance(kMeasuredRoll, kMeasuredRoll) = 0.01 * 0.01;
  m.present[kMeasuredRoll] = false;
  return m;
}

// One step with a measurement made on the spot.
const LaneState& step_with(LaneFilter& f, double dt, const VehicleMotion& motion, const LaneMeasurement& m) {
  return f.step(dt, motion, &m);
}

TEST(LaneFilter, StartsLostAndInitialisesFromTheFirstSolveWithItsCovariance) {
  LaneFilter f;
  EXPECT_EQ(f.state().status, TrackStatus::lost);
  f.step(0.0, {20.0, {}}, nullptr);
  EXPECT_EQ(f.state().status, TrackStatus::lost);
  const LaneState& s = step_with(f, 0.0, {20.0, {}}, measurement(0.2, 0.01, 1e-3, 3.6));
  EXPECT_EQ(s.status, TrackStatus::tentative);
  EXPECT_NEAR(s.value(kOffset), 0.2, 1e-12);
  EXPECT_NEAR(s.value(kWidth), 3.6, 1e-12);
  EXPECT_NEAR(s.value(kHeading), 0.01, 1e-12);
  EXPECT_NEAR(s.value(kCurvature), 1e-3, 1e-12);
  // offset = -(yl + yr) / 2, width = yl - yr, the lines' errors correlated.
  EXPECT_NEAR(s.sigma(kOffset), kLineSigma * std::sqrt((1 + kLineCorrelation) / 2), 1e-12);
  EXPECT_NEAR(s.sigma(kWidth), kLineSigma * std::sqrt(2 * (1 - kLineCorrelation)), 1e-12);
  EXPECT_TRUE(std::isnan(s.sigma(kRoll)));  // roll is the gyro's
  EXPECT_NEAR(s.lateral_velocity_mps, 20.0 * std::sin(0.01), 1e-12);
}

TEST(LaneFilter, ConfirmsAfterTheConfiguredUpdatesThenTracks) {
  LaneFilterConfig c;
  c.confirm_updates = 3;
  LaneFilter f(c);
  const LaneMeasurement m = measurement(0.0, 0.0);
  EXPECT_EQ(f.step(0.033, {20.0, {}}, &m).status, TrackStatus::tentative);
  EXPECT_EQ(f.step(0.033, {20.0, {}}, &m).status, TrackStatus::tentative);
  EXPECT_EQ(f.step(0.033, {20.0, {}}, &m).status, TrackStatus::tracking);
  EXPECT_EQ(f.step(0.033, {20.0, {}}, nullptr).status, TrackStatus::coasting);
}

TEST(LaneFilter, PredictsTheKinematicModel) {
  LaneFilter f;
  f.update(measurement(0.1, 0.02, 2e-3));
  const StateVector before = f.state().value;
  // Without a yaw rate the heading holds; the offset moves by v sin(psi) dt.
  f.predict(0.1, {25.0, {}});
  EXPECT_NEAR(f.state().value(kOffset), before(kOffset) + 25.0 * std::sin(0.02) * 0.1, 1e-12);
  EXPECT_NEAR(f.state().value(kHeading), 0.02, 1e-12);
  EXPECT_EQ(f.state().lateral_acceleration_mps2, 0.0);
  // With one, the heading turns at r - v k: here the vehicle turns less than the road.
  f.predict(0.1, {25.0, 0.03});
  EXPECT_NEAR(f.state().value(kHeading), 0.02 + (0.03 - 25.0 * 2e-3) * 0.1, 1e-12);
  EXPECT_NEAR(f.state().lateral_acceleration_mps2, 25.0 * (0.03 - 25.0 * 2e-3), 1e-12);
  EXPECT_EQ(f.state().value(kCurvature), before(kCurvature));
  EXPECT_EQ(f.state().value(kWidth), before(kWidth));
}

TEST(LaneFilter, CoastsWithGrowingUncertaintyAndIsLostAfterTheCoastTime) {
  LaneFilterConfig c;
  c.coast_s = 0.5;
  LaneFilter f(c);
  f.update(measurement(0.0, 0.0));
  double last_sigma = f.state().sigma(kOffset);
  double t = 0.0;
  while (t + 0.1 <= 0.5 + 1e-9) {
    f.predict(0.1, {20.0, {}});
    t += 0.1;
    ASSERT_NE(f.state().status, TrackStatus::lost) << t;
    EXPECT_GT(f.state().sigma(kOffset), last_sigma);
    last_sigma = f.state().sigma(kOffset);
  }
  f.predict(0.1, {20.0, {}});
  EXPECT_EQ(f.state().status, TrackStatus::lost);
  // And starts afresh from the next solve.
  f.update(measurement(-0.4, 0.0));
  EXPECT_NEAR(f.state().value(kOffset), -0.4, 1e-12);
}

TEST(LaneFilter, GateRefusesAnOutlyingSolveAndKeepsTheState) {
  LaneFilter f;
  const LaneMeasurement m = measurement(0.1, 0.0);
  for (int i = 0; i < 10; ++i) f.step(0.033, {20.0, {}}, &m);
  const StateVector before = f.state().value;
  // Half a metre off (about 20 sigma), not a lane width: a wrong line, not a lane change.
  step_with(f, 0.0, {20.0, {}}, measurement(0.6, 0.0));
  EXPECT_TRUE(f.state().rejected);
  EXPECT_FALSE(f.state().updated);
  EXPECT_EQ(f.state().value, before);
  EXPECT_EQ(f.state().rejections, 1);
  f.step(0.033, {20.0, {}}, &m);
  EXPECT_TRUE(f.state().updated);
  EXPECT_EQ(f.state().rejections, 0);
  EXPECT_LT(f.state().nis, chi_square_quantile(5, 0.999));
}

TEST(LaneFilter, ReassociatesToTheNeighbourLaneInsteadOfAveragingAcrossTheLine) {
  LaneFilter f;
  const double w = 3.6, v = 20.0, psi = std::asin(0.8 / v);  // 0.8 m/s to the left
  double d = 1.5;
  for (int i = 0; i < 10; ++i, d += 0.8 * 0.033) step_with(f, 0.033, {v, {}}, measurement(d, psi));
  // Up to the left line; then the camera crosses it, and the solve sees the lane on the
  // left, the camera near its right line.
  while (d + 0.8 * 0.033 < w / 2) {
    d += 0.8 * 0.033;
    step_with(f, 0.033, {v, {}}, measurement(d, psi));
    ASSERT_TRUE(f.state().updated);
  }
  d += 0.8 * 0.033;
  const LaneState& s = step_with(f, 0.033, {v, {}}, measurement(d - w, psi));
  EXPECT_EQ(s.lane_change, LaneChange::left);
  EXPECT_TRUE(s.updated);
  EXPECT_NEAR(s.value(kOffset), d - w, 0.05);
  EXPECT_NEAR(s.value(kWidth), w, 0.05);
  // And back to the right.
  const LaneState& back = step_with(f, 0.033, {v, {}}, measurement(d - w + 0.03 + w - 0.2, psi));
  EXPECT_EQ(back.lane_change, LaneChange::none);  // 3.4 m off is neither lane: refused
  EXPECT_TRUE(back.rejected);
}

TEST(LaneFilter, ReassociatesToTheRightToo) {
  LaneFilter f;
  const double w = 3.6;
  for (int i = 0; i < 10; ++i) step_with(f, 0.033, {20.0, {}}, measurement(-1.78, -0.02));
  const LaneState& s = step_with(f, 0.033, {20.0, {}}, measurement(-1.8 - 0.02 * 20 * 0.033 + w, -0.02));
  EXPECT_EQ(s.lane_change, LaneChange::right);
  EXPECT_GT(s.value(kOffset), 1.5);
}

TEST(LaneFilter, RestartsFromTheSolveAfterARunOfRefusals) {
  LaneFilterConfig c;
  c.max_rejections = 3;
  LaneFilter f(c);
  for (int i = 0; i < 10; ++i) step_with(f, 0.033, {20.0, {}}, measurement(0.0, 0.0));
  const LaneMeasurement jumped = measurement(0.0, 0.0, 8e-3);  // the curvature 80 sigma away
  for (int i = 0; i < 3; ++i) {
    f.step(0.033, {20.0, {}}, &jumped);
    EXPECT_TRUE(f.state().rejected);
  }
  f.step(0.033, {20.0, {}}, &jumped);
  EXPECT_TRUE(f.state().restarted);
  EXPECT_EQ(f.state().status, TrackStatus::tentative);
  EXPECT_NEAR(f.state().value(kCurvature), 8e-3, 1e-12);
}

TEST(LaneFilter, TracksRollOnlyWhenConfiguredTo) {
  LaneFilterConfig c;
  c.track_roll = true;
  LaneFilter f(c);
  LaneMeasurement m = measurement(0.0, 0.0);
  m.present[kMeasuredRoll] = true;
  m.value(kMeasuredRoll) = 0.01;
  f.update(m);
  EXPECT_NEAR(f.state().value(kRoll), 0.01, 1e-12);
  EXPECT_NEAR(f.state().sigma(kRoll), 0.01, 1e-12);
  LaneFilter without;  // the default: the gyro gives roll
  without.update(m);
  EXPECT_EQ(without.state().value(kRoll), 0.0);
}

// A drive that keeps its lane (offset 0.3 m, heading 0) at 25 m/s with a measured yaw
// rate of 0, seen by a camera yawed 1.4 degrees on the vehicle (the Udacity drives'),
// `seconds` long; or, with bias 0 and heading psi, one that leaves it.
struct Drive {
  double psi = 0.0, bias = 0.0, d0 = 0.3;
  const LaneState& run(LaneFilter& f, double seconds, unsigned seed) const {
    const double dt = 1.0 / 25, v = 25.0;
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> normal;
    const LaneMeasurement shape = measurement(0, 0);
    const Eigen::LLT<MeasurementMatrix> R(shape.covariance);
    double d = d0;
    for (int k = 0; k * dt < seconds; ++k) {
      d += v * std::sin(psi) * dt;
      LaneMeasurement m = measurement(d, psi + bias);
      MeasurementVector n;
      for (int i = 0; i < kMeasurementSize; ++i) n(i) = normal(rng);
      m.value += R.matrixL() * n;
      f.step(k == 0 ? 0.0 : dt, {v, 0.0}, &m);
    }
    return f.state();
  }
};

TEST(LaneFilter, AMountYawedOnTheVehicleIsLearntAsABiasNotTakenForADrift) {
  // Read at face value, the heading would say 25 sin(1.4 deg) = 0.61 m/s towards the
  // left line; the offsets say 0. Within 3 s the filter holds the bias (3 of its sigmas)
  // and no drift (3 sigmas of its lateral velocity).
  const double bias = 1.4 * M_PI / 180;
  for (const unsigned seed : {1u, 2u, 3u}) {
    LaneFilter f;
    const LaneState& s = Drive{0.0, bias}.run(f, 3.0, seed);
    EXPECT_NEAR(s.value(kHeadingBias), bias, 3 * s.sigma(kHeadingBias)) << seed;
    EXPECT_NEAR(s.lateral_velocity_mps, 0.0, 3 * s.sigma_lateral_velocity_mps) << seed;
    EXPECT_LT(s.sigma_lateral_velocity_mps, 0.1) << seed;
    // A new track (the lane lost a while) starts from what this one learnt.
    f.reset();
    const LaneState& again = Drive{0.0, bias}.run(f, 0.04, seed + 10);
    EXPECT_NEAR(again.value(kHeadingBias), bias, 3 * s.sigma(kHeadingBias)) << seed;
    EXPECT_NEAR(again.lateral_velocity_mps, 0.0, 0.15) << seed;
    f.reset_mount();
    EXPECT_EQ((Drive{0.0, bias}.run(f, 0.04, seed).value(kHeadingBias)), 0.0) << "another mount: nothing learnt";
  }
}

TEST(LaneFilter, ATrueHeadingIsNotTakenForTheMount) {
  // Leaving the lane at 1 degree, 0.44 m/s, with a mount that is right: after a second
  // the lateral velocity is the drift's and the bias nought, each within 3 sigmas.
  const double psi = M_PI / 180;
  for (const unsigned seed : {4u, 5u, 6u}) {
    LaneFilter f;
    const LaneState& s = Drive{psi, 0.0, 0.0}.run(f, 1.0, seed);
    EXPECT_NEAR(s.lateral_velocity_mps, 25.0 * std::sin(psi), 3 * s.sigma_lateral_velocity_mps) << seed;
    EXPECT_NEAR(s.value(kHeadingBias), 0.0, 3 * s.sigma(kHeadingBias)) << seed;
  }
}

// A truth that moves exactly as the filter's model says, process noise drawn from the
// model's Q, measurements drawn from R: the Monte Carlo average NEES over M runs at each
// step, times M, is chi-square with M n degrees of freedom (Bar-Shalom, Li, Kirubarajan
// 5.4.2). It lies within the 99 % band at (about) 99 % of the steps.
TEST(LaneFilter, NeesOfAModelConsistentTruthStaysInTheChiSquareBand) {
  constexpr int kRuns = 20, kSteps = 300, kDof = 5;  // offset, heading, curvature, width, pitch
  const double dt = 1.0 / 30, v = 20.0;
  LaneFilterConfig c;
  c.confirm_updates = 1;
  std::vector<double> mean_nees(kSteps, 0.0);
  for (int run = 0; run < kRuns; ++run) {
    std::mt19937_64 rng(1000 + run);
    std::normal_distribution<double> normal;
    LaneFilter f(c);
    StateVector x;
    x << 0.1, 0.01, 1e-3, 3.6, 0.05, 0.0, 0.0;
    const LaneMeasurement shape = measurement(0, 0);
    const Eigen::LLT<MeasurementMatrix> R(shape.covariance);
    auto measure = [&] {
      LaneMeasurement m = shape;
      MeasurementVector n;
      for (int i = 0; i < kMeasurementSize; ++i) n(i) = normal(rng);
      m.value << x(kWidth) / 2 - x(kOffset), -x(kWidth) / 2 - x(kOffset), x(kHeading), x(kCurvature), x(kPitch), 0.0;
      m.value += R.matrixL() * n;
      return m;
    };
    f.update(measure());
    for (int k = 0; k < kSteps; ++k) {
      const double r = 0.02 * std::sin(0.05 * k);  // some steering
      // The truth: the filter's motion model plus its process noise (q * sqrt(dt)).
      const double psi = x(kHeading);
      StateVector w;
      for (int i = 0; i < kStateSize; ++i) w(i) = normal(rng) * std::sqrt(dt);
      const double q_heading = c.heading_noise_rad;
      // Heading noise integrated into the offset (as Q's off-diagonal terms say).
      const double heading_kick = q_heading * w(kHeading);
      x(kOffset) += v * std::sin(psi) * dt + c.offset_noise_m * w(kOffset) + v * std::cos(psi) * heading_kick * dt / 2 +
                    v * std::cos(psi) * q_heading * std::sqrt(dt * dt * dt / 12.0) * normal(rng);
      x(kHeading) += (r - v * x(kCurvature)) * dt + heading_kick;
      x(kCurvature) += c.curvature_noise_per_m * w(kCurvature);
      x(kWidth) += c.width_noise_m * w(kWidth);
      x(kPitch) += c.pitch_noise_rad * w(kPitch);
      const double measured_r = r;  // a perfect gyro: its error is in the heading noise
      f.predict(dt, {v, measured_r});
      f.update(measure());
      const Eigen::Matrix<double, kDof, 1> e = (f.state().value - x).head<kDof>();
      const Eigen::Matrix<double, kDof, kDof> P = f.covariance().topLeftCorner<kDof, kDof>();
      mean_nees[static_cast<std::size_t>(k)] += e.dot(P.llt().solve(e)) / kRuns;
    }
  }
  const double lo = chi_square_quantile(kRuns * kDof, 0.005) / kRuns;
  const double hi = chi_square_quantile(kRuns * kDof, 0.995) / kRuns;
  int inside = 0;
  double overall = 0.0;
  for (const double n : mean_nees) {
    inside += n >= lo && n <= hi;
    overall += n / kSteps;
  }
  EXPECT_GE(inside, static_cast<int>(0.95 * kSteps)) << "band [" << lo << ", " << hi << "], mean " << overall;
  EXPECT_NEAR(overall, kDof, 0.5);
}

TEST(LaneFilter, StepsWithoutAllocating) {
  LaneFilterConfig c;
  c.track_roll = true;
  LaneFilter f(c);
  LaneMeasurement m = measurement(0.1, 0.01);
  LaneMeasurement partial = m;
  partial.present[kMeasuredCurvature] = false;
  const LaneMeasurement outlier = measurement(1.0, 0.01);
  const LaneMeasurement neighbour = measurement(0.1 - 3.6, 0.01);
  f.step(0.0, {20.0, {}}, &m);
  test::AllocationScope scope;
  for (int i = 0; i < 50; ++i) {
    f.step(0.033, {20.0, 0.01}, &m);
    f.step(0.033, {20.0, {}}, &partial);
    f.step(0.033, {20.0, {}}, &outlier);
    f.step(0.033, {20.0, {}}, nullptr);
  }
  f.step(0.033, {20.0, {}}, &neighbour);
  f.reset();
  f.step(0.033, {20.0, {}}, &m);
  EXPECT_EQ(scope.count(), 0u);
}

TEST(LaneFilter, NamesItsStatusesAndLaneChanges) {
  EXPECT_STREQ(to_string(TrackStatus::lost), "lost");
  EXPECT_STREQ(to_string(TrackStatus::tentative), "tentative");
  EXPECT_STREQ(to_string(TrackStatus::tracking), "tracking");
  EXPECT_STREQ(to_string(TrackStatus::coasting), "coasting");
  EXPECT_STREQ(to_string(LaneChange::none), "none");
  EXPECT_STREQ(to_string(LaneChange::left), "left");
  EXPECT_STREQ(to_string(LaneChange::right), "right");
}

}  // namespace
}  // namespace ccdlane::ldw
