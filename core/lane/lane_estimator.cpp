// The per-frame pipeline. Cold starts (no previous frame) detect twice: the pose the
// first solve finds is a far better guess than the nominal mounting to plan rows and
// project marks with. A solve whose picks do not fit well (a stray mark, a line that is
// not a lane line) drops them and solves again, once: the solver is plain least squares.
#include "core/lane/lane_estimator.hpp"

#include <algorithm>
#include <cmath>

#include "core/lane/lane_metrics.hpp"
#include "core/lane/lane_support.hpp"
#include "core/ldw/lane_measurement.hpp"

namespace ccdlane {
namespace {

constexpr double kLineOutlierPx = 3.0;  // a line whose picks miss by this much (RMS) is not a lane line
constexpr double kMinPickOutlierPx = 1.0;

// Share of a line's picks it takes to be fully trusted (marks / (marks + this)).
constexpr double kConfidenceMarks = 10.0;

std::optional<Prior> gyro_prior(const std::optional<Prior>& configured, double gyro_rad, double sigma_deg) {
  if (configured) return configured;  // a [prior] entry overrides the gyro
  return Prior{rad_to_deg(gyro_rad), sigma_deg};
}

}  // namespace

std::string observability_problem(const LaneEstimatorOptions& options, bool roll_measured) {
  const FreeSet& free = options.solver.free;
  const SolverPriors& p = options.priors;
  if (free.has(FreeParam::H) && !p.H_mm)
    return "solver.free: H is free without [prior] H_mm: the camera height is not observable (scale); fix it or add "
           "the prior";
  if (free.has(FreeParam::f) && !p.f_mm)
    return "solver.free: f is free without [prior] f_mm: the focal length is not observable from one image; fix it or "
           "add the prior";
  if (roll_measured || !free.has(FreeParam::phi) || !free.has(FreeParam::y0) || p.phi_deg || p.lane_width_mm) return "";
  return "solver.free: phi and y0 are free with no gyro ([gyro] device), no [prior] phi_deg and no [prior] "
         "lane_width_mm: the roll "
         "is not observable; add one of them or fix phi";
}

LaneEstimator::LaneEstimator(const LaneEstimatorOptions& config)
    : config_(config),
      configured_attitude_(config.nominal_pose.attitude),
      corrected_attitude_(config.nominal_pose.attitude),
      vp_finder_(config.camera, config.detection),
      detector_(config.camera, config.detection),
      solver_(config.camera, config.detection.max_picks, kMaxLaneLines),
      picks_(static_cast<std::size_t>(config.detection.max_picks)),
      residual_px_(picks_.size()),
      scratch_(picks_.size()),
      last_pose_(config.nominal_pose),
      ldw_(config.ldw) {
  reset();
}

void LaneEstimator::reset() {
  config_.nominal_pose.attitude = corrected_attitude_;
  acquisition_ = MountAcquisition{};
  reset_lines();
  ldw_.reset();
}

void LaneEstimator::set_mount_correction(double psi_deg, double theta_deg) {
  corrected_attitude_.psi = configured_attitude_.psi + deg_to_rad(psi_deg);
  corrected_attitude_.theta = configured_attitude_.theta + deg_to_rad(theta_deg);
  if (!acquisition_.adopted) config_.nominal_pose.attitude = corrected_attitude_;
}

Attitude LaneEstimator::mount_for(const Attitude& solved) const {
  // At the start of a run a mount that is clearly off (more than kMountTrustDeg in yaw or
  // pitch from the configured one) is replaced by the picture's: the first frame's solve,
  // then the mean of the first second's (acquire_mount).
  if (acquisition_.done || acquisition_.adopted) return config_.nominal_pose.attitude;
  const Attitude& mount = corrected_attitude_;
  if (std::abs(rad_to_deg(solved.psi - mount.psi)) <= kMountTrustDeg &&
      std::abs(rad_to_deg(solved.theta - mount.theta)) <= kMountTrustDeg)
    return mount;
  Attitude a = mount;
  a.psi = solved.psi;
  a.theta = solved.theta;
  return a;
}

void LaneEstimator::adopt_mount(const Attitude& solved) {
  const Attitude a = mount_for(solved);
  if (acquisition_.done || acquisition_.adopted ||
      (a.psi == corrected_attitude_.psi && a.theta == corrected_attitude_.theta))
    return;
  config_.nominal_pose.attitude = a;
  acquisition_.adopted = true;
}

void LaneEstimator::acquire_mount(const Attitude& solved) {
  // Along a lane the vehicle's heading and pitch average out: the mean of the first ok
  // frames' camera yaw and pitch is the mount (online refinement follows it later, slowly).
  if (acquisition_.done) return;
  MountAcquisition& q = acquisition_;
  ++q.frames;
  q.psi += solved.psi;
  q.theta += solved.theta;
  const double psi = q.psi / q.frames, theta = q.theta / q.frames;
  const Attitude& mount = corrected_attitude_;
  if (q.frames >= kMountAcquisitionFrames) {
    q.done = true;
    q.adopted = q.adopted || std::abs(rad_to_deg(psi - mount.psi)) > kMountTrustDeg ||
                std::abs(rad_to_deg(theta - mount.theta)) > kMountTrustDeg;
  }
  if (q.adopted) {
    config_.nominal_pose.attitude.psi = psi;
    config_.nominal_pose.attitude.theta = theta;
  }
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

CameraPose LaneEstimator::guess_pose(const std::optional<Gx1Angles>& gyro) const {
  CameraPose pose = have_last_ ? last_pose_ : config_.nominal_pose;
  if (gyro) {  // the gyro knows this frame's roll and pitch better than the last frame does
    const Attitude a = camera_attitude_from_gx1(*gyro);
    pose.attitude.theta = a.theta;
    pose.attitude.phi = a.phi;
  }
  return pose;
}

const SolveResult& LaneEstimator::solve(const CameraPose& initial, const std::optional<Gx1Angles>& gyro) {
  SolveRequest req;
  req.mode = config_.solver.mode;
  req.free = config_.solver.free;
  req.line_model = config_.solver.line_model;
  req.pixel_sigma = config_.solver.pixel_sigma;
  req.max_iterations = config_.solver.max_iterations;
  const SolverPriors& p = config_.priors;
  req.priors = {p.psi_deg, p.theta_deg, p.phi_deg, p.H_mm, p.f_mm, p.lane_width_mm};
  if (p.lane_width_mm && num_lines_ > 2) {
    // The solver's lane-width prior holds between the outermost lines; with more than
    // two lines they are k lanes apart, k from the initial lines: k widths, each with
    // its own spread.
    double lo = initial_lines_[0].y0_mm, hi = lo;
    for (int j = 1; j < num_lines_; ++j) {
      lo = std::min(lo, initial_lines_[j].y0_mm);
      hi = std::max(hi, initial_lines_[j].y0_mm);
    }
    const double k = std::max(1.0, std::round((hi - lo) / p.lane_width_mm->mean));
    req.priors.lane_width_mm = Prior{k * p.lane_width_mm->mean, std::sqrt(k) * p.lane_width_mm->sigma};
  }
  if (gyro) {
    const Attitude a = camera_attitude_from_gx1(*gyro);
    req.priors.theta_deg = gyro_prior(p.theta_deg, a.theta, config_.gyro_sigma_deg);
    req.priors.phi_deg = gyro_prior(p.phi_deg, a.phi, config_.gyro_sigma_deg);
  }
  solve_priors_ = req.priors;
  req.initial_pose = initial;
  req.picks = std::span<const Pick>(picks_.data(), static_cast<std::size_t>(num_picks_));
  req.num_lines = num_lines_;
  req.initial_lines = std::span<const LaneLine>(initial_lines_.data(), static_cast<std::size_t>(num_lines_));
  const SolveResult& r = solver_.solve(req);
  solution_ = &r;

  // Reprojection distance of every pick from its solved mark.
  const CameraModel camera(config_.camera, r.pose);
  for (int i = 0; i < num_picks_; ++i) {
    double d = 1e9;
    if (static_cast<std::size_t>(i) < r.points_mm.size()) {
      const Vec2& xy = r.points_mm[i];
      if (const auto px = camera.pixel_from_point(Vec3(xy.x(), xy.y(), 0.0)))
        d = std::hypot(px->x() - picks_[i].px, px->y() - picks_[i].py);
    }
    residual_px_[i] = d;
  }
  return r;
}

bool LaneEstimator::drop_outliers(const SolveResult& result) {
  if (!(result.rms_px > 2.0 * config_.solver.pixel_sigma)) return false;
  // Robust scale of the residuals (median absolute, as a Gaussian sigma).
  std::copy_n(residual_px_.begin(), num_picks_, scratch_.begin());
  const auto mid = scratch_.begin() + num_picks_ / 2;
  std::nth_element(scratch_.begin(), mid, scratch_.begin() + num_picks_);
  const double threshold = std::max(3.0 * 1.4826 * *mid, kMinPickOutlierPx);

  std::array<double, kMaxLaneLines> sum2{};
  std::array<int, kMaxLaneLines> count{};
  for (int i = 0; i < num_picks_; ++i) {
    const auto j = static_cast<std::size_t>(picks_[i].line);
    sum2[j] += residual_px_[i] * residual_px_[i];
    ++count[j];
  }
  // Keep the lines that fit, renumbered in order; within them the picks that fit.
  std::array<int, kMaxLaneLines> new_index{};
  int lines = 0;
  for (int j = 0; j < num_lines_; ++j) {
    const auto k = static_cast<std::size_t>(j);
    const bool fits = count[k] > 0 && std::sqrt(sum2[k] / count[k]) <= kLineOutlierPx;
    new_index[k] = fits ? lines++ : -1;
  }
  int kept = 0;
  for (int i = 0; i < num_picks_; ++i) {
    Pick p = picks_[i];
    const int j = new_index[p.line];
    if (j < 0 || residual_px_[i] > threshold) continue;
    p.line = j;
    picks_[kept++] = p;
  }
  if (kept == num_picks_) return false;
  for (int j = 0; j < num_lines_; ++j) {
    const int k = new_index[j];
    if (k < 0) continue;
    initial_lines_[k] = result.lines[j];
    prior_index_[k] = prior_index_[j];
    detection_line_[k] = detection_line_[j];
  }
  num_lines_ = lines;
  num_picks_ = kept;
  return num_lines_ > 0;
}

const LaneEstimate& LaneEstimator::no_frame(std::uint64_t frame, std::int64_t t_ns, const VehicleInputs& vehicle) {
  estimate_ = LaneEstimate{};
  estimate_.frame = frame;
  estimate_.t_ns = t_ns;
  estimate_.reason = EstimateFailure::no_frame;
  solution_ = nullptr;
  num_picks_ = 0;
  own_left_ = own_right_ = -1;
  miss();
  run_ldw(t_ns, vehicle);
  return estimate_;
}

const LaneEstimate& LaneEstimator::estimate(const ImageView& image, std::uint64_t frame, std::int64_t t_ns,
                                            const std::optional<Gx1Angles>& gyro, const VehicleInputs& vehicle) {
  estimate_ = LaneEstimate{};
  estimate_.frame = frame;
  estimate_.t_ns = t_ns;
  solution_ = nullptr;
  own_left_ = own_right_ = -1;
  support_ = SupportProblem::none;
  speed_mps_ = config_.ldw.vehicle.speed_mps(vehicle.speed_mps);
  estimate_lane(image, gyro);
  run_ldw(t_ns, vehicle);
  return estimate_;
}

void LaneEstimator::run_ldw(std::int64_t t_ns, const VehicleInputs& vehicle) {
  // Only a frame with a lane is a measurement: a rank-deficient solve's lines are not
  // determined, and a frame without both own lines has nothing to place the wheels by.
  ldw::LaneMeasurement measurement;
  const bool measured = estimate_.ok && solution_ && own_left_ >= 0 && own_right_ >= 0;
  if (measured)
    measurement = ldw::measurement_from_solve(*solution_, own_left_, own_right_, config_.nominal_pose.attitude.psi,
                                              config_.ldw.filter.track_roll);
  ldw::LdwFrameInput in;
  in.t_s = static_cast<double>(t_ns) * 1e-9;
  in.speed_mps = vehicle.speed_mps;
  in.yaw_rate_radps = vehicle.yaw_rate_radps;
  in.indicator = vehicle.indicator;
  in.measurement = measured ? &measurement : nullptr;
  in.camera_ok = vehicle.camera_ok;
  in.gyro_ok = vehicle.gyro_ok;
  in.vehicle_ok = vehicle.vehicle_ok;
  in.calibrated = vehicle.calibrated;
  const ldw::LdwResult& r = ldw_.step(in);

  LdwEstimate& out = estimate_.ldw;
  out.available = r.decision.available;
  out.reason = r.decision.reason;
  out.warning = r.decision.warning;
  out.fired = r.decision.fired;
  out.warnings = r.decision.warnings;
  out.track = r.lane.status;
  out.tracked = r.lane.status != ldw::TrackStatus::lost;
  out.dlc_left_mm = r.dlc.left_m * 1e3;
  out.dlc_right_mm = r.dlc.right_m * 1e3;
  out.tlc_left_s = r.tlc_left_s;
  out.tlc_right_s = r.tlc_right_s;
  out.lateral_velocity_mps = r.lateral_velocity_mps;
  out.sigma_lateral_velocity_mps = r.lane.sigma_lateral_velocity_mps;
  out.speed_mps = r.speed_mps;
  out.indicator = vehicle.indicator;
  const ldw::StateVector& x = r.lane.value;
  const ldw::StateVector& sd = r.lane.sigma;
  out.offset_mm = x(ldw::kOffset) * 1e3;
  out.heading_deg = rad_to_deg(x(ldw::kHeading));
  out.curvature_per_m = x(ldw::kCurvature);
  out.lane_width_mm = x(ldw::kWidth) * 1e3;
  out.pitch_deg = rad_to_deg(x(ldw::kPitch));
  out.roll_deg = rad_to_deg(x(ldw::kRoll));
  out.sigma_offset_mm = sd(ldw::kOffset) * 1e3;
  out.sigma_heading_deg = rad_to_deg(sd(ldw::kHeading));
  out.sigma_curvature_per_m = sd(ldw::kCurvature);
  out.sigma_lane_width_mm = sd(ldw::kWidth) * 1e3;
  out.sigma_pitch_deg = rad_to_deg(sd(ldw::kPitch));
  out.sigma_roll_deg = rad_to_deg(sd(ldw::kRoll));
}

void LaneEstimator::take_detection(const DetectionResult& d) {
  detection_ = &d;
  num_lines_ = std::min(d.num_lines, kMaxLaneLines);
  num_picks_ = 0;
  for (const Pick& p : d.picks)
    if (p.line < num_lines_ && num_picks_ < static_cast<int>(picks_.size())) picks_[num_picks_++] = p;
  const FreeSet& free = config_.solver.free;
  for (int j = 0; j < num_lines_; ++j) {
    const LinePrior& fit = d.lines[j].fit;
    // Fixed slopes and curvatures stay at 0 (the road frame is aligned with the lane).
    initial_lines_[j] = {fit.y0_mm, free.has(FreeParam::m) ? fit.m : 0.0, free.has(FreeParam::c) ? fit.c_per_mm : 0.0};
    prior_index_[j] = d.lines[j].prior_index;
    detection_line_[j] = j;
  }
}

EstimateFailure LaneEstimator::attempt(const ImageView& image, const std::optional<Gx1Angles>& gyro) {
  // Detect at detection_pose_, solve; on a cold start look again from where the first
  // solve put the camera; drop what does not fit and solve again. The solve is left in
  // solution_; nothing is committed (tracker, last pose) here.
  const bool cold = !have_last_;
  take_detection(detector_.detect(image, detection_pose_, cold ? std::span<const LinePrior>{} : tracker_.priors()));
  if (num_lines_ == 0 || num_picks_ < config_.detection.min_marks) return EstimateFailure::too_few_marks;
  const SolveResult* r = &solve(detection_pose_, gyro);
  if (cold && r->converged && !r->rank_deficient) {
    std::array<LinePrior, kMaxLaneLines> solved{};
    for (int j = 0; j < r->num_lines; ++j) solved[j] = {r->lines[j].y0_mm, r->lines[j].m, r->lines[j].c_per_mm};
    detection_pose_ = r->pose;
    take_detection(detector_.detect(image, detection_pose_, {solved.data(), static_cast<std::size_t>(r->num_lines)}));
    prior_index_.fill(-1);  // those priors were this frame's own, not a previous frame's lines
    if (num_lines_ == 0 || num_picks_ < config_.detection.min_marks) return EstimateFailure::too_few_marks;
    r = &solve(detection_pose_, gyro);
  }
  if (r->converged && drop_outliers(*r)) {
    if (num_picks_ < config_.detection.min_marks) return EstimateFailure::too_few_marks;
    r = &solve(r->pose, gyro);
  }
  if (r->status == SolveStatus::too_few_picks) return EstimateFailure::too_few_marks;
  // Parameters the picks do not determine leave the cost flat along them, so the solve may
  // wander there without converging: the reason is then that, not the solver.
  if (!r->converged) return r->rank_deficient ? EstimateFailure::rank_deficient : EstimateFailure::solver_failed;
  return r->rank_deficient ? EstimateFailure::rank_deficient : EstimateFailure::none;
}

int LaneEstimator::search_poses(const ImageView& image, const std::optional<Gx1Angles>& gyro,
                                std::array<CameraPose, kMaxSearchPoses>& poses) {
  // Where to start when no previous frame says: the road's vanishing point in the
  // picture, then the mount, then the mount pitched by steps that detection's tolerance
  // (about 4 degrees) covers, out to the search's bound. Roll stays the gyro's (or the
  // mount's); with a gyro its pitch is measured, and the steps are not needed.
  const CameraPose base = guess_pose(gyro);
  int n = 0;
  vanishing_point_ = &vp_finder_.find(image, base);
  if (vanishing_point_->found)
    if (const std::optional<Attitude> a =
            attitude_from_vanishing_point(config_.camera, base, vanishing_point_->x, vanishing_point_->y)) {
      poses[n] = base;
      poses[n].attitude.psi = a->psi;
      if (!gyro) poses[n].attitude.theta = a->theta;
      ++n;
    }
  poses[n++] = base;
  for (int k = 1; !gyro && n + 1 < kMaxSearchPoses && k * kSearchPitchStepDeg <= kSearchPitchDeg; ++k)
    for (const double sign : {+1.0, -1.0}) {
      poses[n] = base;
      poses[n++].attitude.theta += deg_to_rad(sign * k * kSearchPitchStepDeg);
    }
  return n;
}

bool LaneEstimator::supported_from(const SolveResult& r) {
  // Whether this solve is a lane, judged as fill_estimate would (side-effect free): the
  // mount it would be judged against is the one acquisition would take.
  const Attitude mount = config_.nominal_pose.attitude;
  config_.nominal_pose.attitude = mount_for(r.pose.attitude);
  std::array<EstimatedLine, kMaxLaneLines> lines{};
  std::array<int, kMaxLaneLines> order{};
  const int n = ordered_lines(r, lines, order);
  const LaneMetrics m = lane_metrics({lines.data(), static_cast<std::size_t>(n)}, rad_to_deg(r.pose.attitude.psi),
                                     rad_to_deg(config_.nominal_pose.attitude.psi), config_.detection.departure_mm);
  const bool ok = m.has_lane && lane_support_problem(r, order[m.left], order[m.right], m.lane_width_mm, m.heading_deg,
                                                     m.curvature_per_m) == SupportProblem::none;
  config_.nominal_pose.attitude = mount;
  return ok;
}

const LaneEstimate& LaneEstimator::estimate_lane(const ImageView& image, const std::optional<Gx1Angles>& gyro) {
  vanishing_point_ = nullptr;
  estimate_.state = have_last_ ? EstimatorState::tracking : EstimatorState::searching;
  EstimateFailure why = EstimateFailure::none;
  if (have_last_) {
    detection_pose_ = guess_pose(gyro);
    why = attempt(image, gyro);
  } else {
    // Searching: the first starting pose whose solve is a supported lane, else the first
    // pose's outcome (its reason is the frame's).
    std::array<CameraPose, kMaxSearchPoses> poses{};
    const int n = search_poses(image, gyro, poses);
    bool found = false;
    for (int k = 0; k < n && !found; ++k) {
      detection_pose_ = poses[k];
      why = attempt(image, gyro);
      found = why == EstimateFailure::none && supported_from(*solution_);
    }
    if (!found && n > 1) {
      detection_pose_ = poses[0];
      why = attempt(image, gyro);
    }
    if (found) adopt_mount(solution_->pose.attitude);
  }
  if (why != EstimateFailure::none && why != EstimateFailure::rank_deficient) {
    estimate_.ok = false;
    estimate_.reason = why;
    miss();
    return estimate_;
  }
  fill_estimate(*solution_);  // a rank-deficient solve's determined part is still shown
  if (why == EstimateFailure::rank_deficient) {
    estimate_.ok = false;
    estimate_.reason = EstimateFailure::rank_deficient;
  }
  return estimate_;
}

SupportProblem LaneEstimator::lane_support_problem(const SolveResult& r, int left, int right, double lane_width_mm,
                                                   double heading_deg, double curvature_per_m) const {
  const std::span<const Pick> picks(picks_.data(), static_cast<std::size_t>(num_picks_));
  // Each solved line's support, once. A line fitted as a parallel of the others took its
  // direction from them: its marks only say where it is, so it has at most a dash's
  // support, whatever their number (marks of noise lie along any curve parallel to a
  // line of bars).
  std::array<LineSupport, kMaxLaneLines> each{};
  std::array<SupportProblem, kMaxLaneLines> full{};
  int full_lines = 0;
  for (int j = 0; j < r.num_lines; ++j) {
    each[j] = line_support(picks, r.points_mm, j);
    const SupportProblem p = check_line_support(each[j], config_.detection);
    full[j] =
        p == SupportProblem::none && detection_->lines[detection_line_[j]].parallel ? SupportProblem::too_few_marks : p;
    full_lines += full[j] == SupportProblem::none;
  }
  const LineSupport support[2] = {each[left], each[right]};
  const SupportProblem problem[2] = {full[left], full[right]};
  // Both lines need the support of paint along the road, except that one of them may be
  // a single dash (detection takes one only as a parallel of the road's other lines, e.g.
  // a dashed line on a bend) beside a fully supported one, on a road that two fully
  // supported lines establish (one line of bars in noise and a dash beside it made a
  // lane). Its few marks over a metre or two say nothing of how paint narrows with
  // distance: the slope is checked on full lines.
  const bool one_dash_beside_a_line =
      full_lines >= 2 && (problem[0] == SupportProblem::none) != (problem[1] == SupportProblem::none);
  for (int k = 0; k < 2; ++k) {
    if (problem[k] != SupportProblem::none) {
      if (!one_dash_beside_a_line ||
          !check_dash_support(support[k], config_.detection, GroupingParams{}, lane_width_mm))
        return problem[k];
      continue;
    }
    const int line = k == 0 ? left : right;
    if (const SupportProblem p = check_paint_width(paint_width_slope(detection_->marks, detection_line_[line]));
        p != SupportProblem::none)
      return p;
    if (const SupportProblem p =
            check_paint_width_spread(paint_width_spread(detection_->marks, detection_line_[line]), config_.detection);
        p != SupportProblem::none)
      return p;
  }
  const DetectedLine& detected_left = detection_->lines[detection_line_[left]];
  const DetectedLine& detected_right = detection_->lines[detection_line_[right]];
  if (const SupportProblem p =
          check_clutter(lane_clutter(detection_->marks, detected_left.fit, detection_line_[left], detected_right.fit,
                                     detection_line_[right], config_.detection.max_mark_width_mm));
      p != SupportProblem::none)
    return p;
  // The own lane's width against the configured lane width (the solve's own prior may
  // span several lanes); the attitude against the priors this solve had (the gyro's).
  SolverPriors priors = solve_priors_;
  priors.lane_width_mm = config_.priors.lane_width_mm;
  if (const SupportProblem p = check_priors(priors, r.pose, lane_width_mm); p != SupportProblem::none) return p;
  if (const SupportProblem p = check_body_motion(priors, r.pose.attitude, config_.nominal_pose.attitude);
      p != SupportProblem::none)
    return p;
  if (const SupportProblem p = check_heading(heading_deg); p != SupportProblem::none) return p;
  return check_motion(speed_mps_, heading_deg, curvature_per_m);
}

int LaneEstimator::ordered_lines(const SolveResult& r, std::array<EstimatedLine, kMaxLaneLines>& out,
                                 std::array<int, kMaxLaneLines>& order) const {
  std::array<int, kMaxLaneLines> marks{};
  std::array<double, kMaxLaneLines> sum2{};
  for (int i = 0; i < num_picks_; ++i) {
    const auto j = static_cast<std::size_t>(picks_[i].line);
    ++marks[j];
    sum2[j] += residual_px_[i] * residual_px_[i];
  }
  const int n = std::min(r.num_lines, num_lines_);
  // Left to right: largest y0 first (insertion sort, n <= 4).
  for (int j = 0; j < n; ++j) order[j] = j;
  for (int i = 1; i < n; ++i)
    for (int k = i; k > 0 && r.lines[order[k]].y0_mm > r.lines[order[k - 1]].y0_mm; --k)
      std::swap(order[k], order[k - 1]);
  for (int k = 0; k < n; ++k) {
    const auto j = static_cast<std::size_t>(order[k]);
    const LaneLine& l = r.lines[j];
    EstimatedLine& line = out[k];
    line.y0_mm = l.y0_mm;
    line.m = l.m;
    line.c_per_mm = l.c_per_mm;
    line.marks = marks[j];
    // More picks, more trust; a line whose picks miss their marks, less.
    const double line_rms = marks[j] > 0 ? std::sqrt(sum2[j] / marks[j]) : 0.0;
    line.confidence = marks[j] / (marks[j] + kConfidenceMarks) / (1.0 + line_rms * line_rms);
    line.sigma_y0_mm = r.sigma.y0_mm[j];
  }
  return n;
}

void LaneEstimator::fill_estimate(const SolveResult& r) {
  LaneEstimate& e = estimate_;
  e.psi_deg = rad_to_deg(r.pose.attitude.psi);
  e.theta_deg = rad_to_deg(r.pose.attitude.theta);
  e.phi_deg = rad_to_deg(r.pose.attitude.phi);
  e.sigma_psi_deg = r.sigma.psi_deg;
  e.sigma_theta_deg = r.sigma.theta_deg;
  e.sigma_phi_deg = r.sigma.phi_deg;
  e.rms_px = r.rms_px;
  e.iterations = r.iterations;

  // Per line: its picks, their fit, its id; left to right.
  std::array<int, kMaxLaneLines> order{};
  const int n = ordered_lines(r, e.lines, order);
  std::array<LinePrior, kMaxLaneLines> solved{};
  for (int j = 0; j < n; ++j) {
    const LaneLine& l = r.lines[j];
    solved[j] = {l.y0_mm, l.m, l.c_per_mm};
  }
  std::array<int, kMaxLaneLines> ids{};
  tracker_.update({solved.data(), static_cast<std::size_t>(n)}, {prior_index_.data(), static_cast<std::size_t>(n)},
                  {ids.data(), static_cast<std::size_t>(n)});
  e.num_lines = n;
  for (int k = 0; k < n; ++k) e.lines[k].id = ids[static_cast<std::size_t>(order[k])];
  last_pose_ = r.pose;
  have_last_ = true;
  misses_ = 0;

  const LaneMetrics m = lane_metrics({e.lines.data(), static_cast<std::size_t>(n)}, e.psi_deg,
                                     rad_to_deg(config_.nominal_pose.attitude.psi), config_.detection.departure_mm);
  e.heading_deg = m.heading_deg;
  e.curvature_per_m = m.curvature_per_m;
  if (m.left >= 0) own_left_ = order[m.left];
  if (m.right >= 0) own_right_ = order[m.right];
  if (!m.has_lane) {
    e.ok = false;
    e.reason = EstimateFailure::no_lane;
    return;
  }
  // Two lines the right distance apart are not yet a lane: noise makes such pairs. A
  // lane is one only with the support a real one gives (lane_support.hpp).
  support_ = lane_support_problem(r, order[m.left], order[m.right], m.lane_width_mm, m.heading_deg, m.curvature_per_m);
  if (support_ != SupportProblem::none) {
    e.ok = false;
    e.reason = EstimateFailure::no_lane;
    return;
  }
  e.lane_width_mm = m.lane_width_mm;
  e.lateral_offset_mm = m.lateral_offset_mm;
  e.departure = m.departure;
  e.ok = true;
  e.reason = EstimateFailure::none;
  acquire_mount(r.pose.attitude);
}

}  // namespace ccdlane
