// The mount stage on made-up solves: without online refinement it only settles the start
// (a mount 5 degrees off is replaced by the first second's mean, one within 2 degrees
// stands, one beyond the search's reach is not the camera's, reset() starts over); with it, a frame's correction
// applies from the next refine() on, frames without a picture neither count nor move it, a mount learned before is
// where it starts, and one beyond the bounds is "not calibrated".
#include "core/lane/mount_refinement.hpp"

#include <gtest/gtest.h>

#include "core/geometry/types.hpp"

namespace ccdlane {
namespace {

using calibration::OnlineMountState;

constexpr std::int64_t kFrameNs = 1'000'000'000 / 25;

LaneEstimatorOptions options(bool online) {
  LaneEstimatorOptions o;
  o.nominal_pose.attitude = {deg_to_rad(1.0), deg_to_rad(3.0), 0.0};  // psi, theta, phi
  if (online) {
    calibration::OnlineMountOptions m;
    m.configured_psi_deg = 1.0;
    m.configured_theta_deg = 3.0;
    m.frames_needed = 10;
    m.max_change_deg_per_min = 60.0;  // a degree a second
    o.online_mount = m;
  }
  return o;
}

Attitude solved(double psi_deg, double theta_deg) { return {deg_to_rad(psi_deg), deg_to_rad(theta_deg), 0.0}; }

// An ok frame at 90 km/h on straight road solved at (psi_deg, theta_deg).
LaneEstimate frame(int n, double psi_deg, double theta_deg) {
  LaneEstimate e;
  e.t_ns = n * kFrameNs;
  e.ok = true;
  e.num_lines = 2;
  e.psi_deg = psi_deg;
  e.theta_deg = theta_deg;
  e.ldw.speed_mps = 25.0;
  return e;
}

TEST(MountRefinement, AMountClearlyOffIsTheFirstSecondsMeanAndResetStartsOver) {
  MountRefinement m(options(false));
  EXPECT_EQ(m.mount_for(solved(1.5, 3.5)).psi, deg_to_rad(1.0)) << "within the trust: the configured mount";
  m.adopt(solved(1.5, 3.5));
  EXPECT_EQ(m.mount().psi, deg_to_rad(1.0));
  for (int k = 0; k < MountRefinement::kMountAcquisitionFrames; ++k) m.acquire(solved(1.5, 3.5), 3600.0);
  EXPECT_EQ(m.mount().psi, deg_to_rad(1.0)) << "half a degree off stands";

  MountRefinement off(options(false));
  off.adopt(solved(6.0, 3.0));  // the search's first supported lane, 5 degrees off
  EXPECT_NEAR(rad_to_deg(off.mount().psi), 6.0, 1e-12);
  for (int k = 0; k < MountRefinement::kMountAcquisitionFrames; ++k) off.acquire(solved(k % 2 ? 5.0 : 7.0, 3.0), 3600.0);
  EXPECT_NEAR(rad_to_deg(off.mount().psi), (13 * 7.0 + 12 * 5.0) / 25, 1e-9) << "the mean of the first 25 solves";
  EXPECT_TRUE(off.calibrated());
  EXPECT_EQ(off.refine(frame(0, 6.0, 3.0), {}).status.state, OnlineMountState::off);
  off.reset();
  EXPECT_EQ(off.mount().psi, deg_to_rad(1.0));
}

// A solve farther from the configured mount than a search looks (15 degrees) is a fit of
// clutter, not the camera (TuSimple still 40 once took a lane 17 degrees to the side):
// it replaces nothing, and the checks against the mount see it as far off as it is.
TEST(MountRefinement, ASolveBeyondTheSearchsReachIsNotTheMount) {
  for (const Attitude& beyond : {solved(1.0 + 17.0, 3.0), solved(1.0, 3.0 - 16.0)}) {
    MountRefinement m(options(false));
    EXPECT_EQ(m.mount_for(beyond).psi, deg_to_rad(1.0));
    EXPECT_EQ(m.mount_for(beyond).theta, deg_to_rad(3.0));
    m.adopt(beyond);
    EXPECT_EQ(m.mount().psi, deg_to_rad(1.0));
    EXPECT_EQ(m.mount().theta, deg_to_rad(3.0));
  }
  MountRefinement within(options(false));  // 12 degrees off: TuSimple's file with a user's 5 more
  within.adopt(solved(1.0, 3.0 + 12.0));
  EXPECT_NEAR(rad_to_deg(within.mount().theta), 15.0, 1e-12);
}

// The height: a lane-width prior of 3.66 +- 0.3 m, a camera configured at 1.2 m. Lanes
// solved 25 % narrow (a camera 1.6 m up, configured at 1.2) make the height the one that
// gives the prior's width, once, at the end of the first second; lanes within two sigmas
// of the prior leave the configured height; without a prior nothing changes; reset()
// returns to the configured height.
TEST(MountRefinement, AHeightWhoseLanesAreClearlyNotALanesWidthIsTheOneThatGivesThePriorsWidth) {
  LaneEstimatorOptions o = options(false);
  o.nominal_pose.H_mm = 1200.0;
  o.priors.lane_width_mm = Prior{3660.0, 300.0};
  MountRefinement low(o), near(o), unknown(options(false));
  const int n = MountRefinement::kMountAcquisitionFrames;
  for (int k = 0; k < n; ++k) {
    // The true width 3660 seen at 3/4 of the height, +-100 mm of frame-to-frame noise.
    const double width = 0.75 * 3660.0 + (k % 2 ? 100.0 : -100.0) * (k + 1 < n);
    EXPECT_EQ(low.acquire(solved(1.0, 3.0), width), k + 1 == n) << "frame " << k;
    EXPECT_FALSE(near.acquire(solved(1.0, 3.0), 3660.0 - 550.0));
    EXPECT_FALSE(unknown.acquire(solved(1.0, 3.0), 2000.0));
  }
  // The noise cancels over the 24 frames that have it: the mean is 2745 mm, 3/4 of 3660.
  EXPECT_NEAR(low.height_mm(), 1600.0, 1e-9);
  EXPECT_FALSE(low.acquire(solved(1.0, 3.0), 2745.0)) << "once per run";
  EXPECT_EQ(near.height_mm(), 1200.0);
  EXPECT_EQ(unknown.height_mm(), options(false).nominal_pose.H_mm);
  low.reset();
  EXPECT_EQ(low.height_mm(), 1200.0);
}

// A height the user measured ([prior] H_mm as close as a lane's width would say it, or
// closer) is settled from the start: lanes of another width than the prior's (a city
// street's 3 m against a freeway's 3.66) do not move it. A looser height prior leaves it
// to the lanes, as no height prior does.
TEST(MountRefinement, AHeightKnownAsWellAsALanesWidthWouldSayItIsNotMovedByTheLanes) {
  LaneEstimatorOptions o = options(false);
  o.nominal_pose.H_mm = 1200.0;
  o.priors.lane_width_mm = Prior{3660.0, 300.0};  // 8.2 % of the width
  LaneEstimatorOptions measured = o, loose = o, without_lanes = o;
  measured.priors.H_mm = Prior{1200.0, 30.0};  // 2.5 %
  loose.priors.H_mm = Prior{1200.0, 200.0};    // 17 %
  without_lanes.priors.lane_width_mm.reset();
  without_lanes.priors.H_mm = Prior{1200.0, 200.0};
  EXPECT_TRUE(MountRefinement::height_known(measured.priors));
  EXPECT_TRUE(MountRefinement::height_known(without_lanes.priors));
  EXPECT_FALSE(MountRefinement::height_known(loose.priors));
  EXPECT_FALSE(MountRefinement::height_known(o.priors));
  // At the rule's edge: the same relative sigma is known.
  measured.priors.H_mm = Prior{1200.0, 1200.0 * 300.0 / 3660.0};
  EXPECT_TRUE(MountRefinement::height_known(measured.priors));
  MountRefinement known(measured), unsure(loose);
  EXPECT_TRUE(known.height_settled());
  EXPECT_FALSE(unsure.height_settled());
  for (int k = 0; k < MountRefinement::kMountAcquisitionFrames; ++k) {
    EXPECT_FALSE(known.acquire(solved(1.0, 3.0), 3000.0));  // a city street's lanes
    EXPECT_EQ(unsure.acquire(solved(1.0, 3.0), 3000.0), k + 1 == MountRefinement::kMountAcquisitionFrames);
  }
  EXPECT_EQ(known.height_mm(), 1200.0);
  EXPECT_NEAR(unsure.height_mm(), 1200.0 * 3660.0 / 3000.0, 1e-9);
  EXPECT_TRUE(known.height_settled());
}

TEST(MountRefinement, TheCorrectionAFrameBringsAppliesFromTheNextFrameAndFramesWithoutAPictureDoNotCount) {
  MountRefinement m(options(true));
  EXPECT_EQ(m.result().status.state, OnlineMountState::uncalibrated);
  int n = 0;
  for (; n < 10; ++n) EXPECT_TRUE(m.refine(frame(n, 2.0, 2.5), {}).used);
  EXPECT_EQ(m.result().status.state, OnlineMountState::calibrated);
  EXPECT_NEAR(m.result().status.estimate.psi_deg, 1.0, 1e-12);
  EXPECT_NEAR(m.result().status.applied.psi_deg, 0.04, 1e-12) << "a degree a second, one frame's 40 ms";
  EXPECT_NEAR(rad_to_deg(m.mount().psi), 1.0 + m.result().status.applied.psi_deg, 1e-12);
  EXPECT_NEAR(rad_to_deg(m.mount().theta), 3.0 + m.result().status.applied.theta_deg, 1e-12);

  LaneEstimate none = frame(n + 10, 2.0, 2.5);  // ten frames later, with no picture
  none.ok = false;
  none.reason = EstimateFailure::no_frame;
  const calibration::MountAngles before = m.result().status.applied;
  EXPECT_FALSE(m.refine(none, {}).used);
  EXPECT_EQ(m.result().status.applied, before);
  EXPECT_EQ(m.result().status.frames, 10);

  LaneEstimate slow = frame(n + 11, 2.0, 2.5);
  slow.ldw.speed_mps = 10.0;
  EXPECT_FALSE(m.refine(slow, {}).used);
  VehicleInputs turning;
  turning.yaw_rate_radps = 0.1;  // 5.7 degrees a second
  EXPECT_FALSE(m.refine(frame(n + 12, 2.0, 2.5), turning).used);
  EXPECT_EQ(m.result().status.frames, 10);

  m.reset();  // a new run keeps the vehicle's correction
  EXPECT_NEAR(rad_to_deg(m.mount().psi), 1.0 + m.result().status.applied.psi_deg, 1e-12);
}

TEST(MountRefinement, AMountLearnedBeforeIsWhereItStartsAndOneBeyondTheBoundsIsNotCalibrated) {
  LaneEstimatorOptions o = options(true);
  o.learned_mount = calibration::LearnedMount{{0.5, -0.25}, {0.5, -0.25}, {0.1, 0.1}, 500};
  const MountRefinement learned(o);
  EXPECT_EQ(learned.result().status.state, OnlineMountState::calibrated);
  EXPECT_NEAR(rad_to_deg(learned.mount().psi), 1.5, 1e-12);
  EXPECT_NEAR(rad_to_deg(learned.mount().theta), 2.75, 1e-12);

  MountRefinement far(options(true));
  // 7 degrees off: beyond the 6 allowed (a mount known to 5 degrees and a degree's room).
  for (int n = 0; n < 10; ++n) far.refine(frame(n, 8.0, 3.0), {});
  EXPECT_EQ(far.result().status.state, OnlineMountState::out_of_range);
  EXPECT_FALSE(far.calibrated());
  EXPECT_LE(far.result().status.applied.psi_deg, 6.0);
}

}  // namespace
}  // namespace ccdlane
