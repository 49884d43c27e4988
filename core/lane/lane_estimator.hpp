// The per-frame pipeline shared by `ccdlane replay`, `ccdlane calibrate mount` and the
// daemon: a short sequence of stages, each in its own file with a typed result
// (docs/architecture.md "One frame"): detect lane marks (core/detection), fit them
// (lane_fit.hpp: solve with gyro roll/pitch as priors, drop outliers), track the lines
// (tracked_lines.hpp: ids, order, lane metrics), check the lane's support
// (lane_fit.hpp), and run the lane departure warning (core/ldw/ldw_monitor.hpp), into a
// LaneEstimate every field of which is set in one place (report()).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "core/detection/lane_detector.hpp"
#include "core/geometry/gx1_attitude.hpp"
#include "core/lane/frame_inputs.hpp"
#include "core/lane/lane_estimate.hpp"
#include "core/lane/lane_estimator_options.hpp"
#include "core/lane/lane_fit.hpp"
#include "core/lane/lane_support.hpp"
#include "core/lane/lane_tracker.hpp"
#include "core/lane/tracked_lines.hpp"
#include "core/ldw/ldw_monitor.hpp"
#include "core/solver/lane_solver.hpp"

namespace ccdlane {

class LaneEstimator {
 public:
  // Sizes every workspace (detector, solver, pick buffers) from the options. May
  // allocate and throw (std::bad_alloc); estimate() then never does either.
  explicit LaneEstimator(const LaneEstimatorOptions& options);

  // One frame (app/frame_inputs.hpp builds them): its image must be camera.Nu x
  // camera.Nv, or empty for a frame that could not be read (ok = false, no_frame; the
  // lane filter coasts). The result stays valid until the next call. latency_us is left
  // at 0: the caller, who owns the clock, measures it. Frames must come in time order
  // (t_ns drives the lane filter).
  const LaneEstimate& estimate(const FrameInputs& in);

  // The same, for callers that have only these (tests, tools): frame and source_frame
  // are `frame`, the attitude recorded.
  const LaneEstimate& estimate(const ImageView& image, std::uint64_t frame, std::int64_t t_ns,
                               const std::optional<Gx1Angles>& gyro, const VehicleInputs& vehicle = {});
  const LaneEstimate& no_frame(std::uint64_t frame, std::int64_t t_ns, const VehicleInputs& vehicle = {});

  // The online refinement's correction to the configured mount's yaw and pitch
  // (degrees): the pose the heading is measured from and cold starts begin at becomes
  // the configured one plus this. Allocation-free; takes effect from the next frame.
  void set_mount_correction(double psi_deg, double theta_deg);

  // Forgets the previous frames (their pose and lines, and the lane departure warning's
  // track and state).
  void reset();

  // What the last estimate() was made of, for overlays and diagnostics.
  const DetectionResult& detection() const { return fit_.detection(); }
  std::span<const Pick> solved_picks() const { return fit_.picks(); }
  const SolveResult* solution() const { return solution_; }  // null when no solve ran
  const CameraPose& detection_pose() const { return detection_pose_; }
  const ldw::LdwMonitor& ldw_monitor() const { return ldw_; }
  // Why the last estimate()'s lines were not taken for a lane (reason no_lane) although
  // a line lay on each side the right distance apart; none otherwise.
  SupportProblem support_problem() const { return support_; }

 private:
  // The stages, in the order estimate() runs them.
  const SolveResult* detect_and_fit(const ImageView& image, const std::optional<Gx1Angles>& gyro);
  const SolveResult& solve(const CameraPose& initial, const std::optional<Gx1Angles>& gyro);
  void track(const SolveResult& r, const VehicleInputs& vehicle);
  void warn(const FrameInputs& in);
  void report(const FrameInputs& in);

  const SolveResult* fail(EstimateFailure why);
  CameraPose guess_pose(const std::optional<Gx1Angles>& gyro) const;
  void reset_lines();
  void miss();

  LaneEstimatorOptions config_;
  Attitude configured_attitude_;  // config_.nominal_pose's before any mount correction
  bool roll_needs_gyro_;          // observability.hpp: a frame without a gyro reading is roll_unobservable
  LaneDetector detector_;
  LaneFit fit_;
  LaneTracker tracker_;
  ldw::LdwMonitor ldw_;
  CameraPose last_pose_;
  bool have_last_ = false;
  int misses_ = 0;  // frames in a row without an estimate

  // This frame's stage results, which report() turns into the estimate.
  CameraPose detection_pose_;
  EstimateFailure failure_ = EstimateFailure::none;  // of detect and fit
  const SolveResult* solution_ = nullptr;            // the last solve, null when none ran
  const SolveResult* lane_solve_ = nullptr;          // the solve the lines were taken from
  TrackedLines tracked_;
  SupportProblem support_ = SupportProblem::none;
  LaneEstimate estimate_;
};

}  // namespace ccdlane
