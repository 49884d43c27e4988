// The sequencer: each stage's result stays a member until report() makes the estimate of
// them. Cold starts (no previous frame) detect and fit twice: the pose the first solve
// finds is a far better guess than the nominal mounting to plan rows and project marks
// with. A fit whose picks do not fit well drops them and is solved again, once. The mount
// is mount_'s alone: the stages read it, the search and track stages tell it what they
// solved at the start of a run, and its own stage, last, learns from the frame's estimate.
#include "core/lane/lane_estimator.hpp"

#include <algorithm>
#include <cmath>

#include "core/lane/lane_metrics.hpp"
#include "core/lane/observability.hpp"
#include "core/lane/searched_lanes.hpp"
#include "core/ldw/lane_measurement.hpp"

namespace ccdlane {
namespace {

// The picks on the solve's own lane's lines.
int own_lane_picks(const SolveResult& r, std::span<const Pick> picks) {
  const OwnLaneLines own =
      own_lane_lines(std::span<const RoadLine>(r.lines.data(), static_cast<std::size_t>(r.num_lines)));
  return static_cast<int>(std::count_if(picks.begin(), picks.end(),
                                        [&](const Pick& p) { return p.line == own.left || p.line == own.right; }));
}

}  // namespace

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

std::optional<OwnLanePlace> LaneEstimator::own_lane_place(const SolveResult& r) {
  const std::span<const RoadLine> lines(r.lines.data(), static_cast<std::size_t>(r.num_lines));
  const OwnLaneLines own = own_lane_lines(lines);
  if (own.left < 0 || own.right < 0) return std::nullopt;
  return OwnLanePlace{lines[static_cast<std::size_t>(own.left)].y0_mm,
                      lines[static_cast<std::size_t>(own.right)].y0_mm, r.pose.H_mm};
}

std::optional<double> LaneEstimator::own_lane_width(const SolveResult& r) {
  const std::optional<OwnLanePlace> place = own_lane_place(r);
  return place ? std::optional<double>(place->width_mm()) : std::nullopt;
}

bool LaneEstimator::width_agrees_with_height(const SolveResult& r) const {
  if (!height_unsettled()) return true;
  const std::optional<double> width = own_lane_width(r);
  const Prior& prior = *config_.priors.lane_width_mm;
  // The same trust in the configured height as the start of a drive gives it
  // (MountRefinement::acquire).
  return !width || std::abs(*width - prior.mean) <= MountRefinement::kHeightTrustSigmas * prior.sigma;
}

double LaneEstimator::height_scale_for(double pose_H_mm, double mount_H_mm, double own_width_mm,
                                       double prior_width_mm) {
  // Not within a configured height's error of the pose's own height (kUnsettledHeightError,
  // as until 2026-12-06): the pose may be a search step's, itself a guess up to two steps
  // from the mount's. TuSimple still 7's lane, 1.38 lanes wide as seen from the highest
  // step (so 1.23 times the configured height), was left there, and no other pose found
  // its right line, a faint row of raised markers.
  const double span = std::pow(kSearchHeightStep, (kSearchHeights - 1) / 2);
  const double scale = prior_width_mm / own_width_mm;
  const double height = pose_H_mm * scale / mount_H_mm;
  return height >= 1.0 / span && height <= span ? scale : 1.0;
}

LaneEstimator::LaneHeight LaneEstimator::lane_height(bool rescaled, bool width_agrees) {
  if (!rescaled) return width_agrees ? LaneHeight::as_looked_from : LaneHeight::another;
  // Looked at again from the height its first solve's width said, a lane must be a lane's
  // width there: TuSimple still 43's look from 1.62 m (the height a search step's lane
  // gave) took 9 marks 0.9 m right of the camera, inside the lane, for its right line,
  // a lane 3.0 m wide, and the search reported it.
  return width_agrees ? LaneHeight::another : LaneHeight::neither;
}

double LaneEstimator::height_scale(const SolveResult& r) const {
  if (width_agrees_with_height(r)) return 1.0;
  return height_scale_for(r.pose.H_mm, mount_.height_mm(), *own_lane_width(r), config_.priors.lane_width_mm->mean);
}

std::optional<Attitude> LaneEstimator::attitude_from_picture(const ImageView& image, const CameraPose& base) {
  // The lines of bars first: the bars of the searched range's rows at the mount; where
  // they make no point, with those at the mount pitched down by a search's expected
  // error added, which reach farther up should the camera look down more than configured
  // (scanned always, they would reach above the horizon when it does not, where the far
  // road's and cars' bars make lines of their own). Then, where they make none either,
  // the edges' vote. A mount configured looking down much more than the camera does is
  // not helped by either: its rows lie above the road (docs/real-roads.md).
  line_finder_.clear();
  for (const double pitch : {0.0, kSearchPitchErrorDeg}) {
    CameraPose scan = base;
    scan.attitude.theta += deg_to_rad(pitch);
    line_finder_.add(detector_.bars(image, scan), detector_.row_threshold_shares());
    vanishing_point_ = &line_finder_.find(base);
    if (vanishing_point_->found) break;
  }
  if (!vanishing_point_->found) vanishing_point_ = &vp_finder_.find(image, base);
  if (!vanishing_point_->found) return std::nullopt;
  return attitude_from_vanishing_point(config_.camera, base, vanishing_point_->x, vanishing_point_->y);
}

LaneEstimator::SearchPoses LaneEstimator::search_poses(const ImageView& image, const std::optional<Gx1Angles>& gyro,
                                                       std::array<CameraPose, kMaxSearchPoses>& poses) {
  // Where to start when no previous frame says: the road's vanishing point in the
  // picture and that pitched a step either way (kVanishingPitchStepDeg), then the mount,
  // then the mount pitched by steps that detection's tolerance covers, out to the
  // search's bound. Roll stays the gyro's (or the mount's); with a gyro the pitch is
  // measured, and the steps are not needed.
  const CameraPose base = guess_pose(gyro);
  std::array<Attitude, kMaxSearchAttitudes> attitudes{};
  int a = 0;
  if (const std::optional<Attitude> seen = attitude_from_picture(image, base)) {
    attitudes[a] = base.attitude;
    attitudes[a].psi = seen->psi;
    if (!gyro) attitudes[a].theta = seen->theta;
    ++a;
    if (!gyro)  // with a gyro the pitch is measured
      for (const double sign : {+1.0, -1.0}) {
        attitudes[a] = attitudes[0];
        attitudes[a++].theta += deg_to_rad(sign * kVanishingPitchStepDeg);
      }
  }
  attitudes[a++] = base.attitude;
  for (int k = 1; !gyro && a + 1 < kMaxSearchAttitudes && k * kSearchPitchStepDeg <= kSearchPitchDeg; ++k)
    for (const double sign : {+1.0, -1.0}) {
      attitudes[a] = base.attitude;
      attitudes[a++].theta += deg_to_rad(sign * k * kSearchPitchStepDeg);
    }
  // Then each of them at heights a step and two steps higher and lower, while the
  // mount's height is not settled: detection measures marks, dots and gaps in
  // millimetres on the road, and a height a quarter off puts every one of them a quarter
  // off (the lit cap of a raised marker falls below the narrowest taken, lines fall
  // outside their gates).
  const int heights = height_unsettled() ? kSearchHeights : 1;
  int n = 0;
  for (int h = 0; h < heights; ++h) {
    // The configured height, then a step higher and lower, then two.
    const int steps = (h + 1) / 2;
    const double factor = std::pow(kSearchHeightStep, h % 2 == 1 ? steps : -steps);
    for (int k = 0; k < a; ++k) {
      poses[n] = base;
      poses[n].attitude = attitudes[k];
      poses[n++].H_mm *= factor;
    }
  }
  return {n, a};
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

LaneEstimator::Attempt LaneEstimator::search(const ImageView& image, const std::optional<Gx1Angles>& gyro,
                                             const VehicleInputs& vehicle) {
  // Of the starting poses at the first height where one's solve is a supported lane of a
  // lane's width at that height with no line inside it, the one whose own lane's lines
  // hold the most picks (of those within a count's spread of the most, the one whose
  // picks fit best); else the first supported one whose width needed (or needs)
  // another height (and, looked at from the height it said, is a lane's width there),
  // else the first supported one with a line inside it (two lanes from
  // a height taken half as high: lane_support.hpp's kMinInsideLineDashes), else the
  // first supported one with a line found only in the picture (line_in_picture.hpp: the
  // weakest evidence of a lane's line), else the outcome of the pose whose solve had the
  // most picks from marks (the lines it saw, each reported on its own support), or the
  // first pose's when none solved (its reason is the frame's). A lane of the first two
  // kinds that another pose's lane shows to be two lanes (spans_two_lanes) yields to the
  // first lane that does, itself one lane. Why not the first lane:
  // the poses are tried in an order (the picture's vanishing point, the mount, pitched
  // steps), and from each the detection groups other bars, so the first lane depended on
  // how far off the configured mount was (still 0004 lost an own line from a height 10 %
  // off). The own lane is what the search is for; its picks, not all of them, because
  // lines beyond it come with short runs of far dashes and clutter (docs/real-roads.md).
  // The other heights are not looked at once a lane is found: they are guesses for a
  // height the lane's width contradicts, and this one agrees.
  // A lane of a lane's width only at another height is the weaker evidence: from a pose
  // a quarter too low, the own lane's line beside a solid one is too near it to be
  // taken, and the line beyond makes a lane twice as wide with it that a height three
  // quarters as high turns into one of a lane's width; from a pose a quarter too high,
  // the own lane is a third too wide, which the unsettled height's tolerance still takes.
  std::array<CameraPose, kMaxSearchPoses> poses{};
  const SearchPoses searched = search_poses(image, gyro, poses);
  const int n = searched.count;
  Attempt first, lane;
  int lane_pose = -1, lane_picks = 0;  // lane's pose, and the most own-lane picks of a lane
  double lane_rms_px = 0.0;            // lane's solve: its picks' rms, pixels
  int other_height = -1;  // the first pose whose lane is a lane's width only at another height
  SearchedLanes<kMaxSearchPoses> lanes;  // every pose's lane of a lane's width, at either height
  int line_inside = -1;   // the first pose whose lane has a line inside it
  int from_picture = -1;  // the first pose whose lane has a line found only in the picture
  int most_seen = -1, most_picks = 0;  // the pose whose solve, lane or not, had the most picks from marks
  int bent = -1;                       // the first pose whose first solve bent sharply (Attempt::bent)
  int k = 0;
  for (; k < n && !(lane.solve && k % searched.per_height == 0); ++k) {
    detection_pose_ = poses[k];
    const Attempt a = attempt(image, gyro);
    if (a.bent && bent < 0) bent = k;
    const int picks = fit_.picks_from_marks();
    if (const Found found = a.why == EstimateFailure::none ? supported(*a.solve, vehicle) : Found::nothing;
        found == Found::lane_with_a_line_inside) {
      if (line_inside < 0) line_inside = k;
    } else if (found == Found::lane_with_a_line_from_the_picture) {
      if (from_picture < 0) from_picture = k;
    } else if (found == Found::lane) {
      const LaneHeight height = lane_height(a.rescaled, width_agrees_with_height(*a.solve));
      if (const std::optional<OwnLanePlace> place = own_lane_place(*a.solve); place && height != LaneHeight::neither)
        lanes.add(k, *place, height == LaneHeight::as_looked_from);
      if (height == LaneHeight::as_looked_from) {
        // More picks than the best lane's by more than a count's own spread (its Poisson
        // sigma); within it, the count says nothing, and the lane its picks fit better is
        // taken (still 0004 from a mount pitched a degree down: 42 picks against 41 and
        // a line beyond, its left line off its labels near the camera), when better by
        // more than an rms's own spread over that many picks, 1 / sqrt(2 n) of it (a
        // curved Udacity picture's lane from the vanishing point's pose pitched 2 degrees
        // fitted its 95 picks to 0.27 px against 0.28, 6 px off the far dash).
        const int own = own_lane_picks(*a.solve, fit_.picks());
        const double spread = std::sqrt(static_cast<double>(lane_picks));
        const double rms_spread = lane_rms_px / std::sqrt(2.0 * std::max(1, lane_picks));
        if (own > lane_picks + spread ||
            (lane_pose >= 0 && own >= lane_picks - spread && a.solve->rms_px < lane_rms_px - rms_spread)) {
          lane = a;
          lane_picks = std::max(own, lane_picks);
          lane_rms_px = a.solve->rms_px;
          lane_pose = k;
        }
      } else if (height == LaneHeight::another && other_height < 0) {
        other_height = k;
      }
    }
    if (k == 0) first = a;
    if (a.solve && (a.why == EstimateFailure::none || a.why == EstimateFailure::rank_deficient) && picks > most_picks) {
      most_picks = picks;
      most_seen = k;
    }
  }
  // A lane whose line inside (a row of markers that detection from a height half the
  // true one does not see) another pose's lane shows is two lanes; that one is the lane
  // (stills from a mount a quarter too low took the own left line and the next lane's
  // right line at 0.75 m, where other poses had found the lane at 1.6 m).
  int last = k - 1;  // the pose the fit's buffers hold
  if (const int chosen = lane.solve ? lane_pose : other_height; chosen >= 0 && lanes.two_lanes(chosen)) {
    if (const int narrower = lanes.narrower_than(chosen); narrower >= 0 && lanes.as_looked_from(narrower)) {
      lane_pose = narrower;
      detection_pose_ = poses[narrower];
      lane = attempt(image, gyro);
      last = narrower;
    } else if (narrower >= 0) {
      lane = {};
      other_height = narrower;
    }
  }
  if (lane.solve) {
    search_found_from_ = poses[lane_pose];
    have_search_pose_ = true;
    // The fit's buffers hold the last pose's: look again, unless that was the lane's.
    if (lane_pose != last) {
      detection_pose_ = poses[lane_pose];
      lane = attempt(image, gyro);
    }
    lane = with_lines_beyond_again(image, gyro, vehicle, poses[lane_pose], lane);
    mount_.adopt(lane.solve->pose.attitude);
    return lane;
  }
  if (other_height >= 0 || line_inside >= 0 || from_picture >= 0) {
    const int chosen = other_height >= 0 ? other_height : line_inside >= 0 ? line_inside : from_picture;
    detection_pose_ = poses[chosen];
    Attempt a = attempt(image, gyro);
    // A lane of a lane's width at another height is a lane; the weaker kinds are not
    // (look_beyond_again takes only a lane).
    if (chosen == other_height) a = with_lines_beyond_again(image, gyro, vehicle, poses[chosen], a);
    mount_.adopt(a.solve->pose.attitude);
    return a;
  }
  // No lane, and a pose's first solve saw a sharp bend: on one, the marks beyond 10-20 m
  // run tens of degrees off the way to the straight road's point, and the look again
  // refused them (a still on a 60 m bend found its dashed lines' near dashes and none
  // beyond). Looked at again along the bend, as a tracked frame is. Only here: the
  // search's own first solves take their curvature from a few marks, and judged along
  // it every still's bars moved (TuSimple's nominal row lost 2 points of own lines).
  if (bent >= 0) {
    detection_pose_ = poses[bent];
    const Attempt a = attempt(image, gyro, true);
    if (a.why == EstimateFailure::none && supported(*a.solve, vehicle) == Found::lane) {
      mount_.adopt(a.solve->pose.attitude);
      return a;
    }
  }
  // `first` is the fit's buffers' only while no other attempt followed it.
  if (n == 1 && bent < 0) return first;
  // No lane: the pose that saw most, else the first (the fit's buffers hold the last
  // pose's: look again).
  detection_pose_ = poses[most_seen >= 0 ? most_seen : 0];
  return attempt(image, gyro);
}

const SolveResult* LaneEstimator::detect_and_fit(const ImageView& image, const std::optional<Gx1Angles>& gyro,
                                                 const VehicleInputs& vehicle) {
  Attempt a;
  if (have_last_) {
    detection_pose_ = guess_pose(gyro);
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
  return a.solve;
}

LaneEstimator::Attempt LaneEstimator::with_lines_beyond_again(const ImageView& image,
                                                              const std::optional<Gx1Angles>& gyro,
                                                              const VehicleInputs& vehicle, const CameraPose& from,
                                                              Attempt lane) {
  if (const SolveResult* r = look_beyond_again(image, gyro, vehicle, *lane.solve)) {
    lane.solve = r;
    return lane;
  }
  detection_pose_ = from;  // the fit's buffers hold the look's: the lane's again
  return attempt(image, gyro);
}

const SolveResult* LaneEstimator::look_beyond_again(const ImageView& image, const std::optional<Gx1Angles>& gyro,
                                                    const VehicleInputs& vehicle, const SolveResult& lane) {
  // The look again planned its rows and cast its lines beyond the own lane's from the
  // first solve's pose; the lines it found then solved to another. A degree off in pitch
  // or roll moves the road's point 20 px and swings a line 3-4 m beside the own one by
  // tens of pixels at 30 m, where the next lane's Botts' dots are specks: from a first
  // solve a degree or more off, the next lane's line was not found where the solve's own
  // pose finds it (TuSimple stills 27, first solve rolled 5 degrees, and 42, pitched 1.2
  // degrees up). Looked for once more from the lane's solve, along its lines; taken when
  // it adds lines and is the same lane (its width within a mark's width or two), still a
  // lane: taken whenever it was the same lane, the look also moved own lines that were
  // right (docs/real-roads.md).
  const Attitude& from = detection_pose_.attitude;
  const Attitude& to = lane.pose.attitude;
  const double moved =
      std::max({std::abs(to.psi - from.psi), std::abs(to.theta - from.theta), std::abs(to.phi - from.phi)});
  const std::optional<double> width = own_lane_width(lane);
  if (moved < deg_to_rad(kLookBeyondAgainDeg) || !width) return &lane;
  const int lane_lines = lane.num_lines;
  const CameraPose pose = lane.pose;
  std::array<RoadLine, kMaxLaneLines> lines = lane.lines;  // `lane` is the fit's, which the look replaces
  const std::span<const RoadLine> along(lines.data(), static_cast<std::size_t>(lane.num_lines));
  if (!fit_.take(detector_.detect(image, pose, along, PictureSearch::own_lane_and_beyond), true)) return nullptr;
  detection_pose_ = pose;
  const SolveResult* r = &solve(pose, gyro);
  if (r->converged && fit_.drop_outliers(*r) && fit_.enough_picks()) r = &solve(r->pose, gyro);
  if (!r->converged || r->rank_deficient) return nullptr;
  const std::optional<double> again = own_lane_width(*r);
  if (r->num_lines <= lane_lines || !again || std::abs(*again - *width) > kSameLaneWidthMm ||
      supported(*r, vehicle) != Found::lane)
    return nullptr;
  return r;
}

LaneEstimator::Attempt LaneEstimator::look_afresh(const ImageView& image, const std::optional<Gx1Angles>& gyro,
                                                  const VehicleInputs& vehicle) {
  // The previous frame's lines can hold a frame off the lane its picture shows: a line
  // continued onto clutter beside it that the solve then drops, a few yellow marks taking
  // a white line's place. Looked at as a search's pose is, from the same pose (without
  // them, then along its own first solve's lines), then from the pose the last search
  // found its lane from. Four looks where a search takes up to a hundred; taken only as
  // the lane a search would take (at the mount's height, without a line inside it), the
  // lines then starting afresh. Otherwise the tracked look again (the fit's buffers hold
  // the last look's), and its lines coast on as before.
  const CameraPose tracked_from = detection_pose_;
  const LaneTracker tracked = tracker_;
  tracker_.reset();  // judged as a search's lane is, against no previous lines
  const auto a_lane = [&](const Attempt& a) {
    return a.why == EstimateFailure::none && !a.rescaled && width_agrees_with_height(*a.solve) &&
           supported(*a.solve, vehicle) == Found::lane;
  };
  const Attempt fresh = attempt(image, gyro, false, true);
  if (a_lane(fresh)) {
    state_ = EstimatorState::searching;
    return fresh;
  }
  // Then from the pose the last search found the lane from, at the height and roll of
  // now: the lane a search found from one starting pose is not always found again from
  // the pose its solve gave, nor from the next frame's (held stills 39, 71, 79 and 81
  // alternated or lost their lane for a second at a time; still 0002 from a mount 15 %
  // too high lost it once its height was settled).
  if (have_search_pose_) {
    detection_pose_ = search_found_from_;
    detection_pose_.H_mm = tracked_from.H_mm;
    detection_pose_.attitude.phi = tracked_from.attitude.phi;
    const Attempt again = attempt(image, gyro, false, true);
    if (a_lane(again)) {
      state_ = EstimatorState::searching;
      return again;
    }
  }
  tracker_ = tracked;
  // Then as tracked, from the pose the last frame's lane was found from: a solve's pose
  // is not always one its own lane is found again from, while the pose before it was
  // (held still 43's right line, a near piece of 3 m, was found on every second frame:
  // each solve with it gave a pose that missed it, each without one that found it).
  if (have_lane_pose_) {
    detection_pose_ = lane_found_from_;
    detection_pose_.H_mm = tracked_from.H_mm;
    const Attempt again = attempt(image, gyro);
    if (again.why == EstimateFailure::none && supported(*again.solve, vehicle) != Found::nothing) return again;
  }
  detection_pose_ = tracked_from;
  return attempt(image, gyro);
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
