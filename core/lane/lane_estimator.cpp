// The sequencer: each stage's result stays a member until report() makes the estimate of
// them. Cold starts (no previous frame) detect and fit twice: the pose the first solve
// finds is a far better guess than the nominal mounting to plan rows and project marks
// with. A fit whose picks do not fit well drops them and is solved again, once. The mount
// is mount_'s alone: the stages read it, the search and track stages tell it what they
// solved at the start of a run, and its own stage, last, learns from the frame's estimate.
// The search, for a frame without a previous one, is lane_estimator_search.cpp's.
#include "core/lane/lane_estimator.hpp"

#include <algorithm>
#include <cmath>

#include "core/lane/gap_markers.hpp"
#include "core/lane/lane_metrics.hpp"
#include "core/lane/observability.hpp"
#include "core/ldw/lane_measurement.hpp"

namespace ccdlane {

LaneEstimator::LaneEstimator(const LaneEstimatorOptions& config)
    : config_(config),
      roll_needs_gyro_(ccdlane::roll_needs_gyro(config)),
      detector_(config.camera, config.detection),
      fit_(config_),
      ldw_(config.ldw),
      mount_(config),
      last_pose_(config.nominal_pose),
      line_finder_(config.camera, 2 * detector_.max_candidates(), kLineSearch),
      vp_finder_(config.camera, config.detection) {
  reset();
}

void LaneEstimator::reset() {
  mount_.reset();
  reset_lines();
  have_search_pose_ = false;  // a search's pose is of the mount it was found at
  rescaled_ = rescaled_before_ = false;
  ldw_.reset_mount();
}

CameraPose LaneEstimator::nominal_pose() const {
  CameraPose pose = config_.nominal_pose;
  pose.attitude = mount_.mount();
  pose.H_mm = mount_.height_mm();
  return pose;
}

void LaneEstimator::reset_lines() {
  have_last_ = track_had_lane_ = have_lane_pose_ = false;
  misses_ = 0;
  without_lane_ = 0;
  last_pose_ = nominal_pose();
  tracker_.reset();
}

void LaneEstimator::rescale_lines() {
  // On a flat road the picture fixes every distance only in proportion to the height, so
  // the road seen from the new height is the old one scaled about the camera: offsets by
  // the ratio, curvatures by its inverse. Searching afresh instead lost lanes the tracked
  // lines held (held stills 36 and 75: a lane tracked for a second at the height the
  // search took, none found by the search at the acquired one; docs/real-roads.md).
  if (!have_last_) {
    last_pose_ = nominal_pose();
    return;
  }
  tracker_.rescale(mount_.height_mm() / last_pose_.H_mm);
  last_pose_.H_mm = mount_.height_mm();
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
  frame_t_ns_ = in.t_ns;
  vanishing_point_ = nullptr;
  state_ = have_last_ ? EstimatorState::tracking : EstimatorState::searching;
  failure_ = EstimateFailure::none;
  solution_ = lane_solve_ = nullptr;
  tracked_ = TrackedLines{};
  support_ = SupportProblem::none;
  if (!in.image) {
    fit_.clear();
    failure_ = EstimateFailure::no_frame;
    miss();
  } else if (const SolveResult* r = detect_and_fit(*in.image, in.gyro, in.vehicle)) {
    track(*r, in.vehicle);
  }
  warn(in);
  report(in);
  track_had_lane_ = track_had_lane_ || estimate_.ok;
  // The first frame after the height changed that solves lines but makes no lane: the
  // rescaled lines did not hold, and a second of tracked frames would not find it either
  // (held still 61 at the nominal mount: its rescaled lines found the right line alone,
  // rolled 2.4 degrees, and 25 frames went without a lane; still 79 from a height 15 %
  // low, 26). The next frame searches, as a first frame does, at the new height. A frame
  // without a solve (a damaged or empty one) coasts as before.
  const bool lost_at_new_height = rescaled_before_ && lane_solve_ != nullptr;
  rescaled_before_ = false;
  if (estimate_.ok || state_ != EstimatorState::tracking) {
    without_lane_ = 0;
  } else if (++without_lane_ >= kMaxTrackedFramesWithoutLane || lost_at_new_height) {
    reset_lines();
  }
  mount_.refine(estimate_, in.vehicle);
  if (rescaled_) {
    // The height changed (once per run, after a second): the lines and the warning's
    // state are at the old scale. The lines go on rescaled; the warning's filter, whose
    // noise is the old scale's too, starts afresh.
    rescaled_ = false;
    rescaled_before_ = true;
    rescale_lines();
    ldw_.reset();
  }
  return estimate_;
}

CameraPose LaneEstimator::guess_pose(const std::optional<Gx1Angles>& gyro) const {
  CameraPose pose = have_last_ ? last_pose_ : nominal_pose();
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

namespace {

// Two lines or more whose mean curvature is a bend sharper than kTangentRadiusMm.
bool bends_sharply(std::span<const RoadLine> lines) {
  if (lines.size() < 2) return false;
  double mean_c = 0.0;
  for (const RoadLine& l : lines) mean_c += l.c_per_mm / static_cast<double>(lines.size());
  return bends_sharper_than_tangent_radius(mean_c);
}

}  // namespace

LaneEstimator::Attempt LaneEstimator::attempt(const ImageView& image, const std::optional<Gx1Angles>& gyro,
                                              bool along_bend, bool afresh) {
  const bool cold = !have_last_ || afresh;
  bool rescaled = false;
  const std::span<const RoadLine> priors = cold ? std::span<const RoadLine>{} : tracker_.priors();
  // The tracked lines say how the road bends once they made a lane: a track of clutter,
  // which never does, keeps judging bars by the straight road's point.
  const bool bend_confirmed = !cold && track_had_lane_;
  if (!fit_.take(detector_.detect(image, detection_pose_, priors, PictureSearch::own_lane, bend_confirmed)))
    return {nullptr, EstimateFailure::too_few_marks};
  const SolveResult* r = &solve(detection_pose_, gyro);
  bool bent = false;

  if (cold && r->converged && !r->rank_deficient) {
    // Cold start: look again from where the first solve put the camera, along its lines
    // (this frame's own, which no line of the detection continues), and at the height
    // the lane's width says. Every road distance detection gates by (mark and dot
    // widths, ranges) scales with the height; a still has no second to settle it.
    detection_pose_ = r->pose;
    const double scale = height_scale(*r);
    detection_pose_.H_mm *= scale;
    rescaled = scale != 1.0;
    const std::span<const RoadLine> solved(r->lines.data(), static_cast<std::size_t>(r->num_lines));
    bent = bends_sharply(solved);
    if (!fit_.take(detector_.detect(image, detection_pose_, solved, PictureSearch::own_lane_and_beyond,
                                    along_bend && bent),
                   true))
      return {nullptr, EstimateFailure::too_few_marks, false, bent};
    r = &solve(detection_pose_, gyro);
  }
  if (r->converged && fit_.drop_outliers(*r)) {
    if (!fit_.enough_picks()) return {nullptr, EstimateFailure::too_few_marks};
    r = &solve(r->pose, gyro);
  }
  if (r->status == SolveStatus::too_few_picks) return {nullptr, EstimateFailure::too_few_marks};
  // Parameters the picks do not determine leave the cost flat along them, so the solve may
  // wander there without converging: the reason is then that, not the solver.
  if (!r->converged)
    return {nullptr, r->rank_deficient ? EstimateFailure::rank_deficient : EstimateFailure::solver_failed, false, bent};
  return {r, r->rank_deficient ? EstimateFailure::rank_deficient : EstimateFailure::none, rescaled, bent};
}

bool LaneEstimator::height_unsettled() const {
  return config_.priors.lane_width_mm && !mount_.height_settled();
}

double LaneEstimator::motion_speed_mps(const VehicleInputs& vehicle, const OwnLane& own) const {
  return judged_speed_mps(vehicle.speed_mps, config_.ldw.vehicle.configured_speed_mps(), own.curvature_per_m);
}

LaneEstimator::Found LaneEstimator::supported(const SolveResult& r, const VehicleInputs& vehicle) const {
  // Whether this solve is a lane, judged as the track stage would judge it, on a copy of
  // the tracker (nothing is committed) and against the mount acquisition would take.
  const Attitude mount = mount_.mount_for(r.pose.attitude);
  LaneTracker scratch = tracker_;
  const TrackedLines t = track_lines(scratch, r, fit_, rad_to_deg(mount.psi), config_.detection.departure_mm);
  if (!t.metrics.has_lane ||
      fit_.lane_support_problem(r, t.own, motion_speed_mps(vehicle, t.own), mount, mount_.height_settled()) !=
          SupportProblem::none ||
      jumped_from_track(r, t.own, tracker_.priors()))
    return Found::nothing;
  if (fit_.line_from_picture(t.own)) return Found::lane_with_a_line_from_the_picture;
  return fit_.line_inside_lane(t.own) ? Found::lane_with_a_line_inside : Found::lane;
}

bool LaneEstimator::jumped_from_track(const SolveResult& r, const OwnLane& own,
                                      std::span<const RoadLine> tracked) const {
  if (tracked.empty()) return false;
  const OwnLaneLines was = own_lane_lines(tracked);
  const std::span<const int> continues = fit_.prior_index();
  const double dt_s = 1e-9 * static_cast<double>(frame_t_ns_ - tracked_t_ns_);
  if (yaw_jumped(rad_to_deg(r.pose.attitude.psi), rad_to_deg(last_pose_.attitude.psi), dt_s)) return true;
  // The lane a lane change would move the lines by: the tracked one's, else this one's.
  const double width = was.left >= 0 && was.right >= 0 ? tracked[static_cast<std::size_t>(was.left)].y0_mm -
                                                             tracked[static_cast<std::size_t>(was.right)].y0_mm
                                                       : own.lane_width_mm;
  // Each own line against the tracked line it continues; one found anew, against the
  // tracked own line on its side.
  for (const auto& [line, side] : {std::pair{own.left, was.left}, std::pair{own.right, was.right}}) {
    if (line < 0 || static_cast<std::size_t>(line) >= continues.size()) continue;
    const int continued = continues[static_cast<std::size_t>(line)];
    const int before = continued >= 0 ? continued : side;
    if (before < 0 || static_cast<std::size_t>(before) >= tracked.size()) continue;
    if (own_line_jumped(r.lines[static_cast<std::size_t>(line)].y0_mm, tracked[static_cast<std::size_t>(before)].y0_mm,
                        dt_s, width))
      return true;
  }
  return false;
}

namespace {
// The least time a tracked frame's roll walk is given: frames whose times repeat (a
// replay's made-up ones) walk as at 100 frames a second.
constexpr double kMinRollWalkS = 0.01;
}  // namespace

const SolveResult* LaneEstimator::detect_and_fit(const ImageView& image, const std::optional<Gx1Angles>& gyro,
                                                 const VehicleInputs& vehicle) {
  Attempt a;
  fit_.set_previous_roll(std::nullopt);
  if (have_last_) {
    detection_pose_ = guess_pose(gyro);
    const double dt_s = std::max(kMinRollWalkS, 1e-9 * static_cast<double>(frame_t_ns_ - tracked_t_ns_));
    fit_.set_previous_roll(Prior{rad_to_deg(last_pose_.attitude.phi), kRollWalkDegPerSqrtS * std::sqrt(dt_s)});
    a = attempt(image, gyro);
    // A rank-deficient solve is the frame's (roll without a gyro), not the priors'. A
    // lane with a line inside it or a line found only in the picture is still the lane
    // tracked: the look afresh is for a frame without one (looked at on every such
    // frame, a tracked still with its line of dots only in the picture cost 1.1 ms where
    // it had cost 0.7).
    if (a.why != EstimateFailure::rank_deficient &&
        !(a.why == EstimateFailure::none && supported(*a.solve, vehicle) != Found::nothing))
      a = look_afresh(image, gyro, vehicle);
  } else {
    a = search(image, gyro, vehicle);
  }
  if (!a.solve) return fail(a.why);
  if (a.why == EstimateFailure::rank_deficient) failure_ = a.why;  // what was determined is still shown
  if (a.why == EstimateFailure::none && a.solve->converged) return with_gap_markers(*a.solve, gyro);
  return a.solve;
}

const SolveResult* LaneEstimator::with_gap_markers(const SolveResult& r, const std::optional<Gx1Angles>& gyro) {
  const std::span<const RoadLine> lines(r.lines.data(), static_cast<std::size_t>(r.num_lines));
  const OwnLaneLines own = own_lane_lines(lines);
  const CameraModel camera(config_.camera, r.pose);
  std::array<Pick, kMaxGapMarkers> found{};
  int n = 0;
  for (const int j : {own.left, own.right})
    if (j >= 0)
      n += gap_markers(fit_.detection().marks, fit_.picks(), camera, lines[static_cast<std::size_t>(j)], j,
                       std::span<Pick>(found).subspan(static_cast<std::size_t>(n)));
  if (n == 0) return &r;
  // The solve's storage is the next solve's: its pose is kept first.
  const CameraPose from = r.pose;
  const int added = fit_.add_picks({found.data(), static_cast<std::size_t>(n)});
  const SolveResult& with_markers = solve(from, gyro);
  if (with_markers.converged) return &with_markers;
  fit_.remove_last_picks(added);
  return &solve(from, gyro);
}

void LaneEstimator::track(const SolveResult& r, const VehicleInputs& vehicle) {
  lane_solve_ = &r;
  const LaneTracker before = tracker_;
  tracked_ = track_lines(tracker_, r, fit_, rad_to_deg(mount_.mount().psi), config_.detection.departure_mm);
  // Two lines the right distance apart are not yet a lane: noise makes such pairs. A
  // lane is one only with the support a real one gives (lane_support.hpp).
  if (tracked_.metrics.has_lane)
    support_ =
        fit_.lane_support_problem(r, tracked_.own, motion_speed_mps(vehicle, tracked_.own), mount_.mount(),
                                  mount_.height_settled());
  if (tracked_.metrics.has_lane && support_ == SupportProblem::none &&
      jumped_from_track(r, tracked_.own, before.priors())) {
    // The lines and pose tracked stay the last frame's: tracked from this one, the next
    // frame's own line, found where it was, would be a jump from this frame's.
    support_ = SupportProblem::implausible_motion;
    tracker_ = before;
    return;
  }
  last_pose_ = r.pose;
  have_last_ = true;
  misses_ = 0;
  tracked_t_ns_ = frame_t_ns_;
  // The mount's height learns from widths at its own scale (a cold start may have looked
  // from another: height_scale).
  if (failure_ == EstimateFailure::none && tracked_.metrics.has_lane && support_ == SupportProblem::none) {
    rescaled_ = mount_.acquire(r.pose.attitude, tracked_.metrics.lane_width_mm * mount_.height_mm() / r.pose.H_mm);
    lane_found_from_ = detection_pose_;  // the fit's buffers are the last attempt's, this solve's
    have_lane_pose_ = true;
  }
}

void LaneEstimator::warn(const FrameInputs& in) {
  // Only a frame with a lane is a measurement: a rank-deficient solve's lines are not
  // determined, and a frame without both own lines has nothing to place the wheels by.
  const OwnLane& own = tracked_.own;
  const bool measured = failure_ == EstimateFailure::none && lane_solve_ && tracked_.metrics.has_lane &&
                        support_ == SupportProblem::none && own.left >= 0 && own.right >= 0;
  ldw::LaneMeasurement measurement;
  if (measured)
    measurement = ldw::measurement_from_solve(*lane_solve_, own.left, own.right, mount_.mount().psi,
                                              config_.ldw.filter.track_roll);
  ldw::LdwFrameInput ldw_in;
  ldw_in.t_s = static_cast<double>(in.t_ns) * 1e-9;
  ldw_in.speed_mps = in.vehicle.speed_mps;
  ldw_in.yaw_rate_radps = in.vehicle.yaw_rate_radps;
  ldw_in.indicator = in.vehicle.indicator;
  ldw_in.measurement = measured ? &measurement : nullptr;
  ldw_in.camera_ok = in.vehicle.camera_ok;
  ldw_in.gyro_ok = in.vehicle.gyro_ok;
  ldw_in.vehicle_ok = in.vehicle.vehicle_ok;
  // The caller may know the mount is not to be trusted; the mount's refinement may too.
  ldw_in.calibrated = in.vehicle.calibrated && mount_.calibrated();
  ldw_.step(ldw_in);
}

namespace {

// The lines of the own lane and of the lanes beside it: on each side of the vehicle the
// nearest two of the lines reported (ordered left to right), the own lane's and the one
// beyond it. A line two lanes off is seen from far, across the adjacent lane's traffic,
// and is of no use to a departure warning or a lane change; lane benchmarks label the
// own lane's lines and the next on each side (TuSimple: 3 of 3 such lines reported on the
// development stills were beyond those, and false against its labels).
void keep_adjacent_lanes(LaneEstimate& e) {
  int left = 0;
  while (left < e.num_lines && e.lines[static_cast<std::size_t>(left)].y0_mm > 0.0) ++left;
  const int first = std::max(0, left - 2), last = std::min(e.num_lines, left + 2);
  for (int k = first; k < last; ++k)
    e.lines[static_cast<std::size_t>(k - first)] = e.lines[static_cast<std::size_t>(k)];
  e.num_lines = last - first;
}

}  // namespace

void LaneEstimator::report(const FrameInputs& in) {
  LaneEstimate& e = estimate_ = LaneEstimate{};
  e.frame = in.frame;
  e.source_frame = in.source_frame;
  e.t_ns = in.t_ns;
  e.roll_unobservable = in.image && roll_needs_gyro_ && !in.gyro;
  e.state = state_;
  e.ldw = ldw_.estimate();
  const bool lane = tracked_.metrics.has_lane && support_ == SupportProblem::none;
  e.reason = failure_ != EstimateFailure::none ? failure_ : lane ? EstimateFailure::none : EstimateFailure::no_lane;
  e.ok = e.reason == EstimateFailure::none;
  e.support = support_;
  if (!lane_solve_) return;
  const SolveResult& r = *lane_solve_;
  e.psi_deg = rad_to_deg(r.pose.attitude.psi);
  e.theta_deg = rad_to_deg(r.pose.attitude.theta);
  e.phi_deg = rad_to_deg(r.pose.attitude.phi);
  e.H_mm = r.pose.H_mm;
  e.sigma_psi_deg = r.sigma.psi_deg;
  e.sigma_theta_deg = r.sigma.theta_deg;
  e.sigma_phi_deg = r.sigma.phi_deg;
  e.rms_px = r.rms_px;
  e.iterations = r.iterations;
  // The lines with a road's support: the own lane's when it is one, each other line on
  // its own (the issue: the lines beyond the own lane's, "each with the same support
  // rules"); a line of too little road, a parallel placed by the others, or bars that do
  // not narrow as paint is not reported.
  e.num_lines = 0;
  for (int k = 0; k < tracked_.num_lines; ++k) {
    const int j = tracked_.solve_line[k];
    const bool own_line = (j == tracked_.own.left || j == tracked_.own.right);
    if ((own_line && lane) || fit_.line_problem(r, j, lane) == SupportProblem::none)
      e.lines[e.num_lines++] = tracked_.lines[k];
  }
  keep_adjacent_lanes(e);
  const LaneMetrics& m = tracked_.metrics;
  e.heading_deg = m.heading_deg;
  e.curvature_per_m = m.curvature_per_m;
  if (!lane) return;
  e.lane_width_mm = m.lane_width_mm;
  e.lateral_offset_mm = m.lateral_offset_mm;
  e.departure = m.departure;
}

}  // namespace ccdlane
