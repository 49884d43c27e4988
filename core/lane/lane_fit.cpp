// The solver is plain least squares: a solve whose picks do not fit well (a stray mark, a
// line that is not a lane line) is cleaned and solved again by the estimator, once.
#include "core/lane/lane_fit.hpp"

#include <algorithm>
#include <cmath>

#include "core/detection/detection_config.hpp"
#include "core/geometry/gx1_attitude.hpp"
#include "core/lane/lane_metrics.hpp"

namespace ccdlane {
namespace {

constexpr double kLineOutlierPx = 3.0;  // a line whose picks miss by this much (RMS) is not a lane line
constexpr double kMinPickOutlierPx = 1.0;
constexpr double kOutlierSigmas = 3.0;    // a pick further than this many robust sigmas is an outlier
constexpr double kMadToSigma = 1.4826;    // median absolute deviation to a Gaussian's sigma
constexpr double kBadFitSigmas = 2.0;     // a solve whose RMS exceeds this many pixel sigmas fits badly
constexpr double kUnprojectablePx = 1e9;  // the residual of a mark behind the camera

std::optional<Prior> gyro_prior(const std::optional<Prior>& configured, double gyro_rad, double sigma_deg) {
  if (configured) return configured;  // a [prior] entry overrides the gyro
  return Prior{rad_to_deg(gyro_rad), sigma_deg};
}

// Both Gaussians at once (their product, normalised): the configured prior and what the
// previous frame says.
Prior both(const std::optional<Prior>& configured, const Prior& previous) {
  if (!configured || !(configured->sigma > 0.0)) return previous;
  const double w_configured = 1.0 / (configured->sigma * configured->sigma);
  const double w_previous = 1.0 / (previous.sigma * previous.sigma);
  const double w = w_configured + w_previous;
  return Prior{(w_configured * configured->mean + w_previous * previous.mean) / w, 1.0 / std::sqrt(w)};
}

}  // namespace

LaneFit::LaneFit(const LaneEstimatorOptions& options)
    : options_(options),
      min_marks_(options.detection.min_marks),
      solver_(options.camera, options.detection.max_picks, kMaxLaneLines),
      picks_(static_cast<std::size_t>(options.detection.max_picks)),
      residual_px_(picks_.size()),
      scratch_(picks_.size()) {}

bool LaneFit::take(const DetectionResult& d, bool own_priors) {
  detection_ = &d;
  num_lines_ = std::min(d.num_lines, kMaxLaneLines);
  num_picks_ = 0;
  for (const Pick& p : d.picks)
    if (p.line < num_lines_ && num_picks_ < static_cast<int>(picks_.size())) picks_[num_picks_++] = p;
  const FreeSet& free = options_.solver.free;
  for (int j = 0; j < num_lines_; ++j) {
    const RoadLine& fit = d.lines[j].fit;
    // Fixed slopes and curvatures stay at 0 (the road frame is aligned with the lane).
    initial_lines_[j] = {fit.y0_mm, free.has(FreeParam::m) ? fit.m : 0.0, free.has(FreeParam::c) ? fit.c_per_mm : 0.0};
    prior_index_[j] = d.lines[j].prior_index;
    detection_line_[j] = j;
  }
  if (own_priors) prior_index_.fill(-1);
  return num_lines_ > 0 && enough_picks();
}

int LaneFit::add_picks(std::span<const Pick> more) {
  int n = 0;
  for (const Pick& p : more) {
    if (num_picks_ == static_cast<int>(picks_.size())) break;
    picks_[static_cast<std::size_t>(num_picks_++)] = p;
    ++n;
  }
  return n;
}

SolveRequest LaneFit::request(const CameraPose& initial, const std::optional<Gx1Angles>& gyro) const {
  SolveRequest req;
  req.mode = options_.solver.mode;
  req.free = options_.solver.free;
  req.line_model = options_.solver.line_model;
  req.pixel_sigma = options_.solver.pixel_sigma;
  req.max_iterations = options_.solver.max_iterations;
  const SolverPriors& p = options_.priors;
  req.priors = {p.psi_deg, p.theta_deg, p.phi_deg, p.H_mm, p.f_mm, p.lane_width_mm};
  if (p.lane_width_mm && num_lines_ > 2) {
    // The prior holds for the own lane's lines, the nearest on each side of the camera
    // (the outer lines may bound a shoulder); k widths, each with its own spread, when a
    // line between them was not detected. Without a line on each side, between the
    // outermost lines.
    const std::span<const RoadLine> lines(initial_lines_.data(), static_cast<std::size_t>(num_lines_));
    auto [left, right] = own_lane_lines(lines);
    if (left < 0 || right < 0) {
      const auto [lo, hi] = std::minmax_element(lines.begin(), lines.end(),
                                                [](const RoadLine& a, const RoadLine& b) { return a.y0_mm < b.y0_mm; });
      left = static_cast<int>(hi - lines.begin());
      right = static_cast<int>(lo - lines.begin());
    }
    req.priors.lane_width_left = left;
    req.priors.lane_width_right = right;
    const double span = initial_lines_[left].y0_mm - initial_lines_[right].y0_mm;
    const double k = std::max(1.0, std::round(span / p.lane_width_mm->mean));
    req.priors.lane_width_mm = Prior{k * p.lane_width_mm->mean, std::sqrt(k) * p.lane_width_mm->sigma};
  }
  if (num_lines_ == 1 && !gyro && !p.theta_deg) {
    // One line says nothing of the pitch (any pitch projects some road line onto its
    // marks), and a solve left free along it wanders without converging. The pose it was
    // looked for from says the pitch, to within a detection pose's error (bound at two
    // sigmas): solved so, the line is reported, and a search looks again from its pose.
    req.priors.theta_deg = Prior{rad_to_deg(initial.attitude.theta), kSearchPitchErrorDeg / 2.0};
  }
  if (previous_roll_ && !gyro && continues_a_track()) req.priors.phi_deg = both(req.priors.phi_deg, *previous_roll_);
  if (gyro) {
    const Attitude a = camera_attitude_from_gx1(*gyro);
    req.priors.theta_deg = gyro_prior(p.theta_deg, a.theta, options_.gyro_sigma_deg);
    req.priors.phi_deg = gyro_prior(p.phi_deg, a.phi, options_.gyro_sigma_deg);
  }
  req.initial_pose = initial;
  req.picks = picks();
  req.num_lines = num_lines_;
  req.initial_lines = std::span<const RoadLine>(initial_lines_.data(), static_cast<std::size_t>(num_lines_));
  return req;
}

const SolveResult& LaneFit::solve(const CameraPose& initial, const std::optional<Gx1Angles>& gyro) {
  const SolveRequest req = request(initial, gyro);
  solve_priors_ = req.priors;
  const SolveResult& r = solver_.solve(req);
  measure_residuals(r);
  return r;
}

void LaneFit::measure_residuals(const SolveResult& r) {
  // Reprojection distance of every pick from its solved mark.
  const CameraModel camera(options_.camera, r.pose);
  for (int i = 0; i < num_picks_; ++i) {
    double d = kUnprojectablePx;
    if (static_cast<std::size_t>(i) < r.points_mm.size()) {
      const Vec2& xy = r.points_mm[i];
      if (const auto px = camera.pixel_from_point(Vec3(xy.x(), xy.y(), 0.0)))
        d = std::hypot(px->x() - picks_[i].px, px->y() - picks_[i].py);
    }
    residual_px_[i] = d;
  }
}

bool LaneFit::drop_outliers(const SolveResult& result) {
  if (!(result.rms_px > kBadFitSigmas * options_.solver.pixel_sigma)) return false;
  // Robust scale of the residuals (median absolute, as a Gaussian sigma).
  std::copy_n(residual_px_.begin(), num_picks_, scratch_.begin());
  const auto mid = scratch_.begin() + num_picks_ / 2;
  std::nth_element(scratch_.begin(), mid, scratch_.begin() + num_picks_);
  const double threshold = std::max(kOutlierSigmas * kMadToSigma * *mid, kMinPickOutlierPx);

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

SupportProblem LaneFit::line_support_problem(const SolveResult& r, int left, int right, double lane_width_mm) const {
  // Each solved line's support, once. A line fitted as a parallel of the others took its
  // direction from them: its marks only say where it is, so it has at most a dash's
  // support, whatever their number (marks of noise lie along any curve parallel to a
  // line of bars).
  std::array<LineSupport, kMaxLaneLines> each{};
  std::array<SupportProblem, kMaxLaneLines> full{};
  int full_lines = 0;
  for (int j = 0; j < r.num_lines; ++j) {
    each[j] = line_support(picks(), r.points_mm, j);
    full[j] = full_support_problem(each[j], j);
    full_lines += full[j] == SupportProblem::none;
  }
  const LineSupport support[2] = {each[left], each[right]};
  const SupportProblem problem[2] = {full[left], full[right]};
  // Both lines need the support of paint along the road, except that one of them may be
  // a single dash (detection takes one only as a parallel of the road's other lines, e.g.
  // a dashed line on a bend) beside a fully supported one, on a road that two fully
  // supported lines establish (one line of bars in noise and a dash beside it made a
  // lane). Its few marks over a metre or two say nothing of how paint narrows with
  // distance: the slope is checked on full lines. A row of dots is more than a dash when
  // its marks span enough road to have fitted a slope of their own
  // (LineGrouper::kOwnSlopeSpanMm: two groups of separate dots, each round and narrowing
  // with distance), found as a parallel or as a line a little short of a full line's
  // reach; the solve then holds it parallel to the full line, and it needs no second full
  // line. On a road marked with dots alone, the lane's other line is often the only full
  // one.
  const bool one_full = (problem[0] == SupportProblem::none) != (problem[1] == SupportProblem::none);
  // On a bend a dashed lane's lines both leave the view after a dash or two, and each may
  // be a single dash (a 3-lane road at 150 m radius: the solid edge lines are seen along
  // the bend, the own lane's dashes one each). Both may be, when two other lines are
  // fully supported (they give the road's direction and curvature, which the solve
  // shares; a dash only says where its line is) and each dash lies a lane's width from
  // one of them, as well as from the other dash.
  if (problem[0] != SupportProblem::none && problem[1] != SupportProblem::none) {
    if (full_lines < 2) return problem[0];
    for (int k = 0; k < 2; ++k) {
      const int j = k == 0 ? left : right;
      double beside = 1e300;  // the nearest fully supported line
      for (int i = 0; i < r.num_lines; ++i)
        if (full[i] == SupportProblem::none) beside = std::min(beside, std::abs(r.lines[i].y0_mm - r.lines[j].y0_mm));
      if (!has_dash_support(support[k], j, beside) || !has_dash_support(support[k], j, lane_width_mm))
        return problem[k];
    }
    return SupportProblem::none;
  }
  for (int k = 0; k < 2; ++k) {
    const int line = detection_line_[k == 0 ? left : right];
    if (problem[k] != SupportProblem::none) {
      const DetectedLine& d = detection_->lines[static_cast<std::size_t>(line)];
      const bool own_slope = (d.dots && d.far_mm - d.near_mm >= LineGrouper::kOwnSlopeSpanMm) || d.in_picture;
      if (!one_full || (full_lines < 2 && !own_slope) ||
          !has_dash_support(support[k], k == 0 ? left : right, lane_width_mm))
        return problem[k];
      continue;
    }
    if (const SupportProblem p = paint_problem(line); p != SupportProblem::none) return p;
  }
  return SupportProblem::none;
}

SupportProblem LaneFit::paint_problem(int line) const {
  const DetectedLine& detected = detection_->lines[static_cast<std::size_t>(line)];
  // Yellow paint is paint: what its width is for is to tell grey bars of one pixel width
  // (noise, a barrier's lip) from paint, and a yellow edge line often has a worn pale
  // strip or a kerb's lit top beside it that its bars take in on some rows and not on
  // others (TuSimple still 40: 9 to 21 px at one distance).
  if (detected.yellow) return SupportProblem::none;
  const bool dots = detected.dots;
  const double slope =
      dots ? width_distance_slope(detection_->marks, line, true) : paint_width_slope(detection_->marks, line);
  if (const SupportProblem p = check_paint_width(slope); p != SupportProblem::none || dots) return p;
  return check_paint_width_spread(paint_width_spread(detection_->marks, line, scratch_), options_.detection);
}

SupportProblem LaneFit::full_support_problem(const LineSupport& support, int j) const {
  const SupportProblem p = check_line_support(support, options_.detection);
  return p == SupportProblem::none && detection_->lines[static_cast<std::size_t>(detection_line_[j])].parallel
             ? SupportProblem::too_few_marks
             : p;
}

SupportProblem LaneFit::line_problem(const SolveResult& r, int j, bool beside_a_lane) const {
  const LineSupport support = line_support(picks(), r.points_mm, j);
  const SupportProblem p = full_support_problem(support, j);
  if (p == SupportProblem::none || !beside_a_lane) return p;
  // A dash a lane's width from the nearest solved line, as the own lane may have.
  double width = 1e300;
  for (int i = 0; i < r.num_lines; ++i)
    if (i != j) width = std::min(width, std::abs(r.lines[i].y0_mm - r.lines[j].y0_mm));
  return has_dash_support(support, j, width) ? SupportProblem::none : p;
}

bool LaneFit::has_dash_support(const LineSupport& support, int j, double lane_width_mm) const {
  const DetectedLine& d = detection_->lines[static_cast<std::size_t>(detection_line_[j])];
  LineSupport dash = support;
  dash.marks += std::max(0, d.marks - d.num_picks);
  return check_dash_support(dash, options_.detection, GroupingParams{}, lane_width_mm);
}

LaneClutter LaneFit::own_lane_clutter(const OwnLane& own, InsidePieces* line_inside, double faint_share) const {
  const int left = detection_line_[static_cast<std::size_t>(own.left)];
  const int right = detection_line_[static_cast<std::size_t>(own.right)];
  return lane_clutter(detection_->marks, detection_->lines[static_cast<std::size_t>(left)].fit, left,
                      detection_->lines[static_cast<std::size_t>(right)].fit, right,
                      options_.detection.max_mark_width_mm, line_inside, faint_share);
}

bool LaneFit::continues_a_track() const {
  return std::any_of(prior_index_.begin(), prior_index_.begin() + num_lines_, [](int k) { return k >= 0; });
}

bool LaneFit::continues_track(const OwnLane& own) const {
  return prior_index_[static_cast<std::size_t>(own.left)] >= 0 &&
         prior_index_[static_cast<std::size_t>(own.right)] >= 0;
}

bool LaneFit::line_inside_lane(const OwnLane& own) const {
  InsidePieces line;
  own_lane_clutter(own, &line);
  return is_line_inside(line);
}

bool LaneFit::line_from_picture(const OwnLane& own) const {
  for (const int j : {own.left, own.right})
    if (detection_->lines[static_cast<std::size_t>(detection_line_[static_cast<std::size_t>(j)])].in_picture)
      return true;
  return false;
}

int LaneFit::picks_from_marks() const {
  int n = 0;
  for (const Pick& p : picks())
    n += !detection_->lines[static_cast<std::size_t>(detection_line_[static_cast<std::size_t>(p.line)])].in_picture;
  return n;
}

SupportProblem LaneFit::lane_support_problem(const SolveResult& r, const OwnLane& own, double speed_mps,
                                             const Attitude& mount, bool height_settled) const {
  if (const SupportProblem p = line_support_problem(r, own.left, own.right, own.lane_width_mm);
      p != SupportProblem::none)
    return p;
  const double faint_share = continues_track(own) ? kTrackedFaintClutterShare : 0.0;
  if (const SupportProblem p = check_clutter(own_lane_clutter(own, nullptr, faint_share)); p != SupportProblem::none)
    return p;
  // The own lane's width against the configured lane width (the solve's own prior may
  // span several lanes); the attitude against the priors this solve had (the gyro's).
  SolverPriors priors = solve_priors_;
  priors.lane_width_mm = options_.priors.lane_width_mm;
  // Until the start of the run has settled the height (mount_refinement.hpp), widths scale
  // with its error: a lane is one over as wide a range as the height's bound allows.
  if (!height_settled && priors.lane_width_mm)
    priors.lane_width_mm->sigma = std::max(priors.lane_width_mm->sigma, kUnsettledHeightError *
                                                                            priors.lane_width_mm->mean /
                                                                            kPriorAgreementSigmas);
  if (const SupportProblem p = check_priors(priors, r.pose, own.lane_width_mm); p != SupportProblem::none) return p;
  if (const SupportProblem p = check_body_motion(priors, r.pose.attitude, mount); p != SupportProblem::none) return p;
  if (const SupportProblem p = check_heading(own.heading_deg); p != SupportProblem::none) return p;
  return check_motion(speed_mps, own.heading_deg, own.curvature_per_m);
}

}  // namespace ccdlane
