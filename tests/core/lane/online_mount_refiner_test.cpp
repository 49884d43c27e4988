// OnlineMountRefiner against synthetic truth: per-frame angles drawn as the true mount
// plus Gaussian noise of a known sigma, so every tolerance follows from that sigma and
// the number of frames used (the mean's sigma is sigma / sqrt(n)).
#include "core/lane/online_mount_refiner.hpp"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "tests/support/allocation_counter.hpp"

namespace ccdlane::calibration {
namespace {

constexpr double kRateHz = 30.0;
constexpr std::int64_t kFrameNs = static_cast<std::int64_t>(1e9 / kRateHz);

// The configured mount (yaw 0, pitch 5) and the truth 1.5 and -2 degrees off it: the
// issue's mis-mount.
OnlineMountOptions options() {
  OnlineMountOptions o;
  o.configured_psi_deg = 0.0;
  o.configured_theta_deg = 5.0;
  o.frames_needed = 300;
  o.max_correction_deg = 3.0;
  o.max_change_deg_per_min = 6.0;
  return o;
}

struct Drive {
  double true_psi_deg = 1.5, true_theta_deg = 3.0;
  double noise_deg = 0.3;
  std::mt19937_64 rng{7};
  std::int64_t frame = 0;

  MountSample next() {
    std::normal_distribution<double> n(0.0, noise_deg);
    MountSample s;
    s.t_ns = frame++ * kFrameNs;
    s.solved = true;
    s.speed_kmh = 90.0;
    s.curvature_per_m = 1e-5;
    s.psi_deg = true_psi_deg + n(rng);
    s.theta_deg = true_theta_deg + n(rng);
    return s;
  }
};

TEST(OnlineMountRefiner, StartsUncalibratedWithNoCorrection) {
  const OnlineMountRefiner r(options());
  EXPECT_EQ(r.state(), OnlineMountState::uncalibrated);
  EXPECT_EQ(r.progress(), 0.0);
  EXPECT_EQ(r.applied(), MountAngles{});
  EXPECT_STREQ(to_string(OnlineMountState::out_of_range), "out_of_range");
}

TEST(OnlineMountRefiner, CalibratingReportsProgressThenCalibrated) {
  OnlineMountRefiner r(options());
  Drive d;
  for (int i = 0; i < 150; ++i) ASSERT_TRUE(r.add(d.next()));
  EXPECT_EQ(r.state(), OnlineMountState::calibrating);
  EXPECT_DOUBLE_EQ(r.progress(), 0.5);
  EXPECT_EQ(r.applied(), MountAngles{}) << "nothing is applied before the estimate is established";
  for (int i = 0; i < 150; ++i) r.add(d.next());
  EXPECT_EQ(r.state(), OnlineMountState::calibrated);
  EXPECT_DOUBLE_EQ(r.progress(), 1.0);
  const OnlineMountStatus s = r.status();
  EXPECT_EQ(s.state, OnlineMountState::calibrated);
  EXPECT_EQ(s.frames, 300);
  EXPECT_EQ(s.estimate, r.estimate());
  EXPECT_EQ(s.sigma, r.sigma());
  EXPECT_EQ(s.applied, r.applied());
}

TEST(OnlineMountRefiner, EstimateConvergesToTheTrueMountWithinItsSigma) {
  OnlineMountRefiner r(options());
  Drive d;
  constexpr int kFrames = 3000;  // below the 10 x frames_needed memory: the plain mean
  for (int i = 0; i < kFrames; ++i) r.add(d.next());
  const double expected_sigma = d.noise_deg / std::sqrt(kFrames);
  // The reported sigma is the sample spread over sqrt(n): within a few % of the truth's
  // (the spread's own relative sigma is 1/sqrt(2n) = 1.3 %; 4 of those).
  EXPECT_NEAR(r.sigma().psi_deg, expected_sigma, 0.052 * expected_sigma);
  EXPECT_NEAR(r.sigma().theta_deg, expected_sigma, 0.052 * expected_sigma);
  EXPECT_NEAR(r.spread().psi_deg, d.noise_deg, 0.052 * d.noise_deg);
  // 4 sigma: a correct estimator fails this once in 16000 runs (and the seed is fixed).
  EXPECT_NEAR(r.estimate().psi_deg, 1.5, 4 * expected_sigma);
  EXPECT_NEAR(r.estimate().theta_deg, -2.0, 4 * expected_sigma);
}

TEST(OnlineMountRefiner, AppliedCorrectionMovesAtTheBoundedRateAndReachesTheEstimate) {
  OnlineMountRefiner r(options());
  Drive d;
  const double max_step = options().max_change_deg_per_min / 60.0 / kRateHz;
  MountAngles before = r.applied();
  double longest_step = 0.0;
  // 1.5 degrees at 6 degrees a minute: 15 s (450 frames) after the 300 needed; twice that.
  for (int i = 0; i < 300 + 900; ++i) {
    r.add(d.next());
    longest_step = std::max({longest_step, std::abs(r.applied().psi_deg - before.psi_deg),
                             std::abs(r.applied().theta_deg - before.theta_deg)});
    before = r.applied();
  }
  EXPECT_LE(longest_step, max_step * (1 + 1e-9));
  EXPECT_GT(longest_step, 0.9 * max_step) << "it moved at the full rate while far from the estimate";
  // At the end the applied correction sits on the (still refining) estimate, which moves
  // by far less than a step a frame.
  EXPECT_NEAR(r.applied().psi_deg, r.estimate().psi_deg, max_step);
  EXPECT_NEAR(r.applied().theta_deg, r.estimate().theta_deg, max_step);
}

TEST(OnlineMountRefiner, AGapInTheFramesDoesNotMakeTheCorrectionJump) {
  OnlineMountRefiner r(options());
  Drive d;
  for (int i = 0; i < 300; ++i) r.add(d.next());
  const MountAngles before = r.applied();
  MountSample late = d.next();
  late.t_ns += 600'000'000'000;  // ten minutes later
  r.add(late);
  EXPECT_LE(std::abs(r.applied().psi_deg - before.psi_deg), options().max_change_deg_per_min / 60.0 + 1e-12);
}

TEST(OnlineMountRefiner, FramesOffTheStraightFastLaneAreNotUsed) {
  OnlineMountRefiner r(options());
  Drive d;
  for (int i = 0; i < 400; ++i) r.add(d.next());
  const MountAngles good = r.estimate();
  // Each would drag the mean 5 degrees off if it were used.
  auto bad = [&](auto&& spoil) {
    MountSample s = d.next();
    s.psi_deg += 5.0;
    s.theta_deg -= 5.0;
    spoil(s);
    return r.add(s);
  };
  for (int i = 0; i < 100; ++i) {
    EXPECT_FALSE(bad([](MountSample& s) { s.solved = false; }));
    EXPECT_FALSE(bad([](MountSample& s) { s.speed_kmh = 30.0; }));
    EXPECT_FALSE(bad([](MountSample& s) { s.curvature_per_m = -1.0 / 400.0; }));
    EXPECT_FALSE(bad([](MountSample& s) { s.yaw_rate_deg_s = 5.0; }));
    EXPECT_FALSE(bad([](MountSample& s) { s.psi_deg = std::nan(""); }));
  }
  EXPECT_EQ(r.estimate(), good);
  EXPECT_EQ(r.counts().unsolved, 200);
  EXPECT_EQ(r.counts().slow, 100);
  EXPECT_EQ(r.counts().curved, 100);
  EXPECT_EQ(r.counts().turning, 100);
  EXPECT_EQ(r.counts().used, 400);
}

TEST(OnlineMountRefiner, GrossOutliersAreRejected) {
  OnlineMountRefiner r(options());
  Drive d;
  std::mt19937_64 rng(3);
  std::bernoulli_distribution wrong(0.05);
  constexpr int kFrames = 3000;
  int gross = 0;
  for (int i = 0; i < kFrames; ++i) {
    MountSample s = d.next();
    if (i >= 100 && wrong(rng)) {  // a solve on a stray line: 5 degrees off
      s.psi_deg += 5.0;
      ++gross;
    }
    r.add(s);
  }
  EXPECT_EQ(r.counts().outliers, gross) << "4 sigma gate: 5 degrees is 17 sigma";
  const double sigma = d.noise_deg / std::sqrt(static_cast<double>(r.counts().used));
  EXPECT_NEAR(r.estimate().psi_deg, 1.5, 4 * sigma);
}

TEST(OnlineMountRefiner, AMountBeyondTheBoundsIsOutOfRangeAndTheCorrectionStopsAtTheBound) {
  OnlineMountRefiner r(options());
  Drive d;
  d.true_psi_deg = 4.0;  // 4 degrees off a 3 degree bound
  for (int i = 0; i < 300 + 30 * 60; ++i) r.add(d.next());
  EXPECT_EQ(r.state(), OnlineMountState::out_of_range);
  EXPECT_NEAR(r.estimate().psi_deg, 4.0, 4 * d.noise_deg / std::sqrt(2100.0));
  EXPECT_DOUBLE_EQ(r.applied().psi_deg, 3.0);
}

TEST(OnlineMountRefiner, AMountThatMovesIsFollowedWithinTheMemory) {
  OnlineMountOptions o = options();
  o.memory_frames = 600;
  OnlineMountRefiner r(o);
  Drive d;
  for (int i = 0; i < 1200; ++i) r.add(d.next());
  d.true_psi_deg = 0.0;  // knocked 1.5 degrees (5 sigma of a frame)
  for (int i = 0; i < 10 * 600; ++i) r.add(d.next());
  // The old mount's weight is down to (1 - 1/600)^6000 = 5e-5 of the mean.
  EXPECT_NEAR(r.estimate().psi_deg, 0.0, 4 * d.noise_deg / std::sqrt(600.0));
}

TEST(OnlineMountRefiner, RestoredIsCalibratedAtOnceFromTheLearnedCorrection) {
  OnlineMountRefiner r(options());
  LearnedMount learned{{1.4, -1.9}, {1.2, -1.5}, {0.3, 0.3}, 5000};
  r.restore(learned);
  EXPECT_EQ(r.state(), OnlineMountState::calibrated);
  EXPECT_EQ(r.applied(), learned.applied);
  EXPECT_NEAR(r.estimate().psi_deg, 1.4, 1e-12);
  EXPECT_NEAR(r.estimate().theta_deg, -1.9, 1e-12);
  EXPECT_EQ(r.learned().frames, 5000);
}

TEST(OnlineMountRefiner, AddAllocatesNothing) {
  OnlineMountRefiner r(options());
  Drive d;
  std::vector<MountSample> samples;
  for (int i = 0; i < 2000; ++i) samples.push_back(d.next());
  test::AllocationScope counter;
  for (const MountSample& s : samples) r.add(s);
  (void)r.learned();
  EXPECT_EQ(counter.count(), 0u);
}

}  // namespace
}  // namespace ccdlane::calibration
