// The per-frame pipeline shared by `ccdlane replay` and the daemon: detect lane marks,
// solve attitude and lines (gyro roll/pitch as priors), follow line ids, turn the lines
// into lane width, offset, heading and departure, and run the lane departure warning
// (lane filter, DLC/TLC, decision) on the solve (a LaneEstimate).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/detection/detection_config.hpp"
#include "core/detection/lane_detector.hpp"
#include "core/detection/vanishing_point.hpp"
#include "core/geometry/gx1_attitude.hpp"
#include "core/lane/lane_estimate.hpp"
#include "core/lane/lane_support.hpp"
#include "core/lane/lane_tracker.hpp"
#include "core/ldw/ldw_monitor.hpp"
#include "core/solver/lane_solver.hpp"
#include "core/solver/solver_options.hpp"

namespace ccdlane {

// What the estimator is built from (the configuration maps onto it: Config::estimator_options).
struct LaneEstimatorOptions {
  CameraSpec camera;
  CameraPose nominal_pose;  // the mount: the guess before any frame, and the yaw heading is measured from
  SolverOptions solver;
  SolverPriors priors;          // a prior here overrides the gyro's for the same angle
  double gyro_sigma_deg = 0.5;  // the gyro's roll and pitch become priors with this sigma
  DetectionConfig detection;
  // The lane departure warning, with the vehicle. filter.track_roll: without a gyro
  // (the solve's roll then is the only measure of it).
  ldw::LdwConfig ldw;
};

// What the vehicle tells about this frame (a CAN gateway's vehicle_state_t, or replay's
// frames.csv columns), and the health the caller knows of.
struct VehicleInputs {
  std::optional<double> speed_mps;       // empty: [vehicle] speed_kmh
  std::optional<double> yaw_rate_radps;  // + turning left; empty: none measured
  ldw::TurnIndicator indicator = ldw::TurnIndicator::none;
  bool camera_ok = true;   // false: the camera stalled or failed (LDW "camera_fault")
  bool gyro_ok = true;     // false: a configured gyro is not delivering ("gyro_fault")
  bool vehicle_ok = true;  // false: the gateway sends only refused states or stopped ("vehicle_fault")
  bool calibrated = true;  // false: the mount is outside its allowed bounds (LDW "not_calibrated")
};

// Why solves set up as `options` say cannot determine what they are asked for, "" when
// they can (docs/solver.md "What is and is not observable"): scale and focal length never
// are from one image of parallel lines; roll about the lane direction is absorbed by
// moving free lines sideways unless the gyro (`roll_measured`: the frames come with its
// reading), a roll prior or a lane-width prior pins it. The daemon refuses to start on
// such a configuration and replay on such a recording.
std::string observability_problem(const LaneEstimatorOptions& options, bool roll_measured);

class LaneEstimator {
 public:
  // Sizes every workspace (detector, solver, pick buffers) from the options. May
  // allocate and throw (std::bad_alloc); estimate() then never does either.
  explicit LaneEstimator(const LaneEstimatorOptions& options);

  // One frame: `image` must be camera.Nu x camera.Nv. `gyro` is the 3DM-GX1 reading at
  // this frame, if any; `vehicle` the vehicle's state at it. The result stays valid
  // until the next call. latency_us is left at 0: the caller, who owns the clock, fills
  // it in. Frames must come in time order (t_ns drives the lane filter).
  const LaneEstimate& estimate(const ImageView& image, std::uint64_t frame, std::int64_t t_ns,
                               const std::optional<Gx1Angles>& gyro, const VehicleInputs& vehicle = {});

  // A frame that could not be read: ok = false (no_frame); the lane filter coasts.
  const LaneEstimate& no_frame(std::uint64_t frame, std::int64_t t_ns, const VehicleInputs& vehicle = {});

  // The online refinement's correction to the configured mount's yaw and pitch
  // (degrees): the pose the heading is measured from and cold starts begin at becomes
  // the configured one plus this. Allocation-free; takes effect from the next frame.
  void set_mount_correction(double psi_deg, double theta_deg);

  // Forgets the previous frames (their pose and lines, and the lane departure warning's
  // track and state).
  void reset();

  // What the last estimate() was made of, for overlays and diagnostics.
  const DetectionResult& detection() const { return *detection_; }
  std::span<const Pick> solved_picks() const { return {picks_.data(), static_cast<std::size_t>(num_picks_)}; }
  const SolveResult* solution() const { return solution_; }  // null when no solve ran
  const CameraPose& detection_pose() const { return detection_pose_; }
  // The vanishing point the last estimate() looked for (searching), null when it went on
  // from the previous frame.
  const VanishingPoint* vanishing_point() const { return vanishing_point_; }
  // The mount the estimator goes by: the configured one (with the online correction), or
  // what the road showed when that was more than kMountTrustDeg off.
  const Attitude& mount() const { return config_.nominal_pose.attitude; }
  // How far the mount the picture shows may lie from the configured one before the
  // picture's is taken: a configured mount is a measurement too, within a degree or two.
  static constexpr double kMountTrustDeg = 2.0;
  // The ok frames whose solved yaw and pitch settle the mount at the start (1 s at 25 fps).
  static constexpr int kMountAcquisitionFrames = 25;
  // A search without a previous frame also starts from the mount pitched by these steps,
  // out to this bound: detection finds lines from a pose within about 4 degrees.
  static constexpr double kSearchPitchStepDeg = 3.0;
  static constexpr double kSearchPitchDeg = 9.0;
  const ldw::LdwMonitor& ldw_monitor() const { return ldw_; }
  // Why the last estimate()'s lines were not taken for a lane (reason no_lane) although
  // a line lay on each side the right distance apart; none otherwise.
  SupportProblem support_problem() const { return support_; }

 private:
  const LaneEstimate& estimate_lane(const ImageView& image, const std::optional<Gx1Angles>& gyro);
  void run_ldw(std::int64_t t_ns, const VehicleInputs& vehicle);
  void reset_lines();
  CameraPose guess_pose(const std::optional<Gx1Angles>& gyro) const;
  void take_detection(const DetectionResult& d);
  EstimateFailure attempt(const ImageView& image, const std::optional<Gx1Angles>& gyro);
  static constexpr int kMaxSearchPoses = 8;
  int search_poses(const ImageView& image, const std::optional<Gx1Angles>& gyro,
                   std::array<CameraPose, kMaxSearchPoses>& poses);
  bool supported_from(const SolveResult& r);
  int ordered_lines(const SolveResult& r, std::array<EstimatedLine, kMaxLaneLines>& out,
                    std::array<int, kMaxLaneLines>& order) const;
  Attitude mount_for(const Attitude& solved) const;
  void adopt_mount(const Attitude& solved);
  void acquire_mount(const Attitude& solved);
  const SolveResult& solve(const CameraPose& initial, const std::optional<Gx1Angles>& gyro);
  bool drop_outliers(const SolveResult& result);
  void fill_estimate(const SolveResult& result);
  SupportProblem lane_support_problem(const SolveResult& r, int left, int right, double lane_width_mm,
                                      double heading_deg, double curvature_per_m) const;
  void miss();

  LaneEstimatorOptions config_;
  Attitude configured_attitude_;  // config_.nominal_pose's before any mount correction
  Attitude corrected_attitude_;   // configured plus the online correction: what reset() returns to
  // The mount's acquisition at the start of a run: the solved yaw and pitch of its first
  // ok frames, summed.
  struct MountAcquisition {
    int frames = 0;
    double psi = 0.0, theta = 0.0;
    bool adopted = false;  // the picture's mount is in use
    bool done = false;
  } acquisition_;
  VanishingPointFinder vp_finder_;
  const VanishingPoint* vanishing_point_ = nullptr;
  LaneDetector detector_;
  LaneSolver solver_;
  LaneTracker tracker_;
  const DetectionResult* detection_ = nullptr;
  const SolveResult* solution_ = nullptr;
  CameraPose detection_pose_;
  // The picks and initial lines of the current solve (detection's, minus outliers).
  std::vector<Pick> picks_;
  int num_picks_ = 0;
  int num_lines_ = 0;
  std::array<LaneLine, kMaxLaneLines> initial_lines_{};
  std::array<int, kMaxLaneLines> prior_index_{};     // per solver line: detection's prior_index
  std::array<int, kMaxLaneLines> detection_line_{};  // per solver line: its line in detection()
  std::vector<double> residual_px_;                  // per pick, of the last solve
  std::vector<double> scratch_;
  CameraPose last_pose_;
  bool have_last_ = false;
  int misses_ = 0;             // frames in a row without an estimate
  SolverPriors solve_priors_;  // of the last solve
  SupportProblem support_ = SupportProblem::none;
  double speed_mps_ = 0.0;  // this frame's (the vehicle's input, else [vehicle] speed_kmh)
  // The own lane's lines of the last fill_estimate, as indices into the solve's lines
  // (-1: none): the lane filter's measurement.
  int own_left_ = -1, own_right_ = -1;
  ldw::LdwMonitor ldw_;
  LaneEstimate estimate_;
};

}  // namespace ccdlane
