// The sequencer: each stage's result stays a member until report() makes the estimate of
// them. Cold starts (no previous frame) detect and fit twice: the pose the first solve
// finds is a far better guess than the nominal mounting to plan rows and project marks
// with. A fit whose picks do not fit well drops them and is solved again, once.
#include "core/lane/lane_estimator.hpp"

#include "core/lane/observability.hpp"
#include "core/ldw/lane_measurement.hpp"

namespace ccdlane {

LaneEstimator::LaneEstimator(const LaneEstimatorOptions& config)
    : config_(config),
      configured_attitude_(config.nominal_pose.attitude),
      roll_needs_gyro_(ccdlane::roll_needs_gyro(config)),
      detector_(config.camera, config.detection),
      fit_(config_),
      ldw_(config.ldw),
      last_pose_(config.nominal_pose) {
  reset();
}

void LaneEstimator::reset() {
  reset_lines();
  ldw_.reset();
}

void LaneEstimator::set_mount_correction(double psi_deg, double theta_deg) {
  config_.nominal_pose.attitude.psi = configured_attitude_.psi + deg_to_rad(psi_deg);
  config_.nominal_pose.attitude.theta = configured_attitude_.theta + deg_to_rad(theta_deg);
}

void LaneEstimator::reset_lines() {
  have_last_ = false;
  misses_ = 0;
  last_pose_ = config_.nominal_pose;
  tracker_.reset();
}

void LaneEstimator::miss() {
  // A frame or two without an estimate (a damaged frame, a truck in the way): the last
  // pose and the lines, coasting, are still the best guess. After that, start afresh.
  // The lane filter coasts on its own clock ([ldw] coast_s): it is not reset here.
  tracker_.coast();
  if (++misses_ > LaneTracker::kCoastFrames) reset_lines();
}

const LaneEstimate& LaneEstimator::estimate(const ImageView& image, std::uint64_t frame, std::int64_t t_ns,
                                            const std::optional<Gx1Angles>& gyro, const VehicleInputs& vehicle) {
  return estimate(
      FrameInputs{frame, frame, t_ns, image, gyro, gyro ? AttitudeSource::recorded : AttitudeSource::none, vehicle});
}

const LaneEstimate& LaneEstimator::no_frame(std::uint64_t frame, std::int64_t t_ns, const VehicleInputs& vehicle) {
  return estimate(FrameInputs{frame, frame, t_ns, std::nullopt, std::nullopt, AttitudeSource::none, vehicle});
}

const LaneEstimate& LaneEstimator::estimate(const FrameInputs& in) {
  failure_ = EstimateFailure::none;
  solution_ = lane_solve_ = nullptr;
  tracked_ = TrackedLines{};
  support_ = SupportProblem::none;
  if (!in.image) {
    fit_.clear();
    failure_ = EstimateFailure::no_frame;
    miss();
  } else if (const SolveResult* r = detect_and_fit(*in.image, in.gyro)) {
    track(*r, in.vehicle);
  }
  warn(in);
  report(in);
  return estimate_;
}

CameraPose LaneEstimator::guess_pose(const std::optional<Gx1Angles>& gyro) const {
  CameraPose pose = have_last_ ? last_pose_ : config_.nominal_pose;
  if (gyro) {  // the gyro knows this frame's roll and pitch better than the last frame does
    const Attitude a = camera_attitude_from_gx1(*gyro);
    pose.attitude.theta = a.theta;
    pose.attitude.phi = a.phi;
  }
  return pose;
}

const SolveResult* LaneEstimator::fail(EstimateFailure why) {
  failure_ = why;
  miss();
  return nullptr;
}

const SolveResult& LaneEstimator::solve(const CameraPose& initial, const std::optional<Gx1Angles>& gyro) {
  solution_ = &fit_.solve(initial, gyro);
  return *solution_;
}

const SolveResult* LaneEstimator::detect_and_fit(const ImageView& image, const std::optional<Gx1Angles>& gyro) {
  detection_pose_ = guess_pose(gyro);
  const std::span<const RoadLine> priors = have_last_ ? tracker_.priors() : std::span<const RoadLine>{};
  if (!fit_.take(detector_.detect(image, detection_pose_, priors))) return fail(EstimateFailure::too_few_marks);
  const SolveResult* r = &solve(detection_pose_, gyro);

  if (!have_last_ && r->converged && !r->rank_deficient) {
    // Cold start: look again from where the first solve put the camera, along its lines
    // (this frame's own, which no line of the detection continues).
    detection_pose_ = r->pose;
    const std::span<const RoadLine> solved(r->lines.data(), static_cast<std::size_t>(r->num_lines));
    if (!fit_.take(detector_.detect(image, detection_pose_, solved), true)) return fail(EstimateFailure::too_few_marks);
    r = &solve(detection_pose_, gyro);
  }
  if (r->converged && fit_.drop_outliers(*r)) {
    if (!fit_.enough_picks()) return fail(EstimateFailure::too_few_marks);
    r = &solve(r->pose, gyro);
  }
  if (r->status == SolveStatus::too_few_picks) return fail(EstimateFailure::too_few_marks);
  // Parameters the picks do not determine leave the cost flat along them, so the solve may
  // wander there without converging: the reason is then that, not the solver.
  if (!r->converged) return fail(r->rank_deficient ? EstimateFailure::rank_deficient : EstimateFailure::solver_failed);
  if (r->rank_deficient) failure_ = EstimateFailure::rank_deficient;  // what was determined is still shown
  return r;
}

void LaneEstimator::track(const SolveResult& r, const VehicleInputs& vehicle) {
  lane_solve_ = &r;
  tracked_ =
      track_lines(tracker_, r, fit_, rad_to_deg(config_.nominal_pose.attitude.psi), config_.detection.departure_mm);
  last_pose_ = r.pose;
  have_last_ = true;
  misses_ = 0;
  // Two lines the right distance apart are not yet a lane: noise makes such pairs. A
  // lane is one only with the support a real one gives (lane_support.hpp).
  if (tracked_.metrics.has_lane)
    support_ = fit_.lane_support_problem(r, tracked_.own, config_.ldw.vehicle.speed_mps(vehicle.speed_mps),
                                         config_.nominal_pose.attitude);
}

void LaneEstimator::warn(const FrameInputs& in) {
  // Only a frame with a lane is a measurement: a rank-deficient solve's lines are not
  // determined, and a frame without both own lines has nothing to place the wheels by.
  const OwnLane& own = tracked_.own;
  const bool measured = failure_ == EstimateFailure::none && lane_solve_ && tracked_.metrics.has_lane &&
                        support_ == SupportProblem::none && own.left >= 0 && own.right >= 0;
  ldw::LaneMeasurement measurement;
  if (measured)
    measurement = ldw::measurement_from_solve(*lane_solve_, own.left, own.right, config_.nominal_pose.attitude.psi,
                                              config_.ldw.filter.track_roll);
  ldw::LdwFrameInput ldw_in;
  ldw_in.t_s = static_cast<double>(in.t_ns) * 1e-9;
  ldw_in.speed_mps = in.vehicle.speed_mps;
  ldw_in.yaw_rate_radps = in.vehicle.yaw_rate_radps;
  ldw_in.indicator = in.vehicle.indicator;
  ldw_in.measurement = measured ? &measurement : nullptr;
  ldw_in.camera_ok = in.vehicle.camera_ok;
  ldw_in.gyro_ok = in.vehicle.gyro_ok;
  ldw_in.calibrated = in.vehicle.calibrated;
  ldw_.step(ldw_in);
}

void LaneEstimator::report(const FrameInputs& in) {
  LaneEstimate& e = estimate_ = LaneEstimate{};
  e.frame = in.frame;
  e.source_frame = in.source_frame;
  e.t_ns = in.t_ns;
  e.roll_unobservable = in.image && roll_needs_gyro_ && !in.gyro;
  e.ldw = ldw_.estimate();
  const bool lane = tracked_.metrics.has_lane && support_ == SupportProblem::none;
  e.reason = failure_ != EstimateFailure::none ? failure_ : lane ? EstimateFailure::none : EstimateFailure::no_lane;
  e.ok = e.reason == EstimateFailure::none;
  if (!lane_solve_) return;
  const SolveResult& r = *lane_solve_;
  e.psi_deg = rad_to_deg(r.pose.attitude.psi);
  e.theta_deg = rad_to_deg(r.pose.attitude.theta);
  e.phi_deg = rad_to_deg(r.pose.attitude.phi);
  e.sigma_psi_deg = r.sigma.psi_deg;
  e.sigma_theta_deg = r.sigma.theta_deg;
  e.sigma_phi_deg = r.sigma.phi_deg;
  e.rms_px = r.rms_px;
  e.iterations = r.iterations;
  e.num_lines = tracked_.num_lines;
  e.lines = tracked_.lines;
  const LaneMetrics& m = tracked_.metrics;
  e.heading_deg = m.heading_deg;
  e.curvature_per_m = m.curvature_per_m;
  if (!lane) return;
  e.lane_width_mm = m.lane_width_mm;
  e.lateral_offset_mm = m.lateral_offset_mm;
  e.departure = m.departure;
}

}  // namespace ccdlane
