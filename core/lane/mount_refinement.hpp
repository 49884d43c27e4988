// The mount the lane estimator goes by, and the stage that refines it: the one place that
// owns it. It starts as the configured mount (plus a correction learned before), is
// replaced by what the road shows when that is clearly off at the start of a run
// (docs/real-roads.md "The mount, settled at the start"), and, with online refinement
// configured, follows what the frames' solves say while driving (online_mount_refiner.hpp).
// The estimator runs refine() as the last stage of each frame: what a frame teaches
// applies from the next one, so nothing outside writes into the estimator mid-run.
#pragma once

#include <optional>

#include "core/geometry/attitude.hpp"
#include "core/lane/frame_inputs.hpp"
#include "core/lane/lane_estimate.hpp"
#include "core/lane/lane_estimator_options.hpp"
#include "core/lane/online_mount_refiner.hpp"

namespace ccdlane {

// What the online refinement made of the last frame, and where it stands after it.
struct MountRefinementResult {
  bool used = false;                      // this frame counted toward the estimate
  calibration::OnlineMountStatus status;  // state off when online refinement is not configured
  calibration::LearnedMount learned;      // what a state file keeps, to start from next time
};

class MountRefinement {
 public:
  // How far the mount the picture shows may lie from the configured one before the
  // picture's is taken: a configured mount is a measurement too, within a degree or two.
  static constexpr double kMountTrustDeg = 2.0;
  // How far from the configured mount a search looks for the road (LaneEstimator's
  // kLineSearch): a solve farther off, in yaw or pitch, is not the camera's but a fit of
  // clutter, and does not replace the mount (TuSimple still 40 once took a lane at 9
  // degrees up and 17 degrees to the side, and adopting its attitude let it pass the
  // checks against the mount).
  static constexpr double kMountReachDeg = 15.0;
  // The ok frames whose solved yaw and pitch settle the mount at the start (1 s at 25 fps).
  static constexpr int kMountAcquisitionFrames = 25;
  // How many of the lane-width prior's sigmas the first second's mean lane width may lie
  // from the prior's mean before the height is taken from it: lanes differ from their
  // nominal width by a sigma or so; a height 25 % off makes them 25 % off.
  static constexpr double kHeightTrustSigmas = 2.0;

  // options.nominal_pose.attitude is the configured mount; online_mount and learned_mount
  // say whether it is refined online and from what. Allocation-free from here on.
  explicit MountRefinement(const LaneEstimatorOptions& options);

  // The mount in use: the one the heading is measured from and cold starts begin at.
  const Attitude& mount() const { return mount_; }
  // The mount's height in use: the configured one, or the one the first second's lane
  // widths gave when the lane-width prior disagreed with it (acquire).
  double height_mm() const { return height_mm_; }
  // Whether the height is settled: the first second's lanes have said, there is no
  // lane-width prior to say anything, or the height is known (height_known). Until then
  // lane widths are judged loosely, a search also looks from other heights, and a lane
  // whose width is no lane's at the configured height gives the height.
  bool height_settled() const { return !lane_width_prior_ || height_known_ || acquisition_.done; }
  // Whether `[prior] H_mm` says the height as closely as a lane's width would, or more
  // (relative sigmas; no lane-width prior: any height prior): the user measured it, and
  // lanes narrower or wider than the prior's (a city street, a bridge) must not move it.
  // A looser height prior leaves the height for the lanes to settle.
  static bool height_known(const SolverPriors& priors);

  // The start of a run. What the mount would be for a frame whose solve is `solved`, were
  // it the run's first supported lane (a search judges its candidates against this).
  Attitude mount_for(const Attitude& solved) const;
  // The search found a supported lane solved at `solved`.
  void adopt(const Attitude& solved);
  // An ok frame with a supported lane, solved at `solved` with this lane width: one of
  // the first second's. True when it changed the height: every road distance the
  // estimator holds is then at the old scale.
  bool acquire(const Attitude& solved, double lane_width_mm);

  // The online stage, after the frame's estimate: a frame with a picture is a sample
  // (one without says nothing of the mount, and its time must not move the correction),
  // and the correction it leaves applies from the next frame.
  const MountRefinementResult& refine(const LaneEstimate& estimate, const VehicleInputs& vehicle);
  const MountRefinementResult& result() const { return result_; }
  // False while the mount learned lies beyond the correction's bounds: the lane departure
  // warning is then unavailable ("not_calibrated").
  bool calibrated() const;

  // A new run: the start's acquisition again, from the configured mount and the online
  // correction (which is the vehicle's, not the run's, and is kept).
  void reset();

 private:
  // Whether one frame's solve replaces the mount (mount_for, adopt): the start's
  // acquisition has not decided yet and the solve is clearly off the mount.
  bool replaced_by(const Attitude& solved) const;
  void apply_correction();

  Attitude configured_;  // the configuration's
  Attitude corrected_;   // configured plus the online correction: what reset() returns to
  Attitude mount_;       // in use
  std::optional<Prior> lane_width_prior_;
  bool height_known_ = false;
  double configured_height_mm_ = 0.0;
  double height_mm_ = 0.0;  // in use
  // The solved yaw and pitch of the run's first ok frames, summed.
  struct Acquisition {
    int frames = 0;
    double psi = 0.0, theta = 0.0, lane_width_mm = 0.0;
    bool adopted = false;  // the picture's mount is in use
    bool done = false;
  } acquisition_;
  std::optional<calibration::OnlineMountRefiner> online_;
  MountRefinementResult result_;
};

}  // namespace ccdlane
