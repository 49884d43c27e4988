// The search, for a frame without a previous one to go on (lane_estimator.hpp): the
// poses it starts from (the picture's vanishing point, the mount, pitched steps, heights),
// the lane it takes among theirs, the height a lane's width says, and the looks again:
// from the lane's solve for the lines beyond it, and afresh where a track lost its lane.
#include <algorithm>
#include <cmath>

#include "core/lane/lane_estimator.hpp"
#include "core/lane/search_choice.hpp"

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

std::optional<OwnLanePlace> LaneEstimator::own_lane_place(const SolveResult& r) {
  const std::span<const RoadLine> lines(r.lines.data(), static_cast<std::size_t>(r.num_lines));
  const OwnLaneLines own = own_lane_lines(lines);
  if (own.left < 0 || own.right < 0) return std::nullopt;
  return OwnLanePlace{lines[static_cast<std::size_t>(own.left)].y0_mm, lines[static_cast<std::size_t>(own.right)].y0_mm,
                      r.pose.H_mm};
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

LaneEstimator::Attempt LaneEstimator::search(const ImageView& image, const std::optional<Gx1Angles>& gyro,
                                             const VehicleInputs& vehicle) {
  // Of the starting poses at the first height where one's solve is a supported lane of a
  // lane's width at that height with no line inside it, the one whose own lane's lines
  // hold the most picks (of those within a count's spread of the most, the one whose
  // solve holds the most of the road's lines, then the one whose picks fit best:
  // searched_lanes.hpp, ranks_above); else the first supported one whose width needed (or needs)
  // another height (and, looked at from the height it said, is a lane's width there),
  // else the first supported one with a line inside it (two lanes from
  // a height taken half as high: lane_support.hpp's kMinInsideLineDashes), else the
  // first supported one with a line found only in the picture (line_in_picture.hpp: the
  // weakest evidence of a lane's line), else the outcome of the pose whose solve had the
  // most picks from marks (the lines it saw, each reported on its own support), or the
  // first pose's when none solved (its reason is the frame's). A lane of the first two
  // kinds that another pose's lane shows to be two lanes (spans_two_lanes) yields to the
  // first lane that does, itself one lane. A pose whose solve is lone (reached from
  // fewer than half as many poses as the most reached attitude: solved_attitudes.hpp)
  // gives none of these while another pose gives one. Why not the first lane:
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
  const int n = std::min(searched.count, kMaxSearchPoses);
  Attempt first, lane, last_attempt;
  std::array<std::optional<LaneRank>, kMaxSearchPoses> ranks{};  // each pose's lane at its height, as ranked
  std::array<SearchedKind, kMaxSearchPoses> kinds{};             // what each pose's solve was
  SearchedLanes<kMaxSearchPoses> lanes;        // every pose's lane of a lane's width, at either height
  SolvedAttitudes<kMaxSearchPoses> attitudes;  // where every pose's solve converged
  int most_seen = -1, most_picks = 0;          // the pose whose solve, lane or not, had the most picks from marks
  int bent = -1;                               // the first pose whose first solve bent sharply (Attempt::bent)
  bool have_lane = false;
  int k = 0;
  for (; k < n && !(have_lane && k % searched.per_height == 0); ++k) {
    detection_pose_ = poses[k];
    const Attempt a = attempt(image, gyro);
    if (a.bent && bent < 0) bent = k;
    const int picks = fit_.picks_from_marks();
    if (a.why == EstimateFailure::none) attitudes.add(k, a.solve->pose.attitude.theta, a.solve->pose.attitude.psi);
    SearchedKind& kind = kinds[static_cast<std::size_t>(k)];
    if (const Found found = a.why == EstimateFailure::none ? supported(*a.solve, vehicle) : Found::nothing;
        found == Found::lane_with_a_line_inside) {
      kind = SearchedKind::line_inside;
    } else if (found == Found::lane_with_a_line_from_the_picture) {
      kind = SearchedKind::from_picture;
    } else if (found == Found::lane) {
      const LaneHeight height = lane_height(a.rescaled, width_agrees_with_height(*a.solve));
      if (const std::optional<OwnLanePlace> place = own_lane_place(*a.solve); place && height != LaneHeight::neither)
        lanes.add(k, *place, height == LaneHeight::as_looked_from);
      if (height == LaneHeight::as_looked_from) {
        kind = SearchedKind::lane;
        ranks[static_cast<std::size_t>(k)] =
            LaneRank{own_lane_picks(*a.solve, fit_.picks()), a.solve->num_lines, a.solve->rms_px};
        have_lane = true;
      } else if (height == LaneHeight::another) {
        kind = SearchedKind::other_height;
      }
    }
    if (k == 0) first = a;
    last_attempt = a;
    if (a.solve && (a.why == EstimateFailure::none || a.why == EstimateFailure::rank_deficient) && picks > most_picks) {
      most_picks = picks;
      most_seen = k;
    }
  }
  // The lane: the best ranked of the poses' lanes at the height where one first was, then
  // the first of each weaker kind, not a lone solve's while another pose gave one
  // (search_choice.hpp); nor is a lone solve's lane then evidence that another is two lanes.
  const SearchChoice choice = choose_searched<kMaxSearchPoses>(kinds, ranks, attitudes, k);
  if (choice.lone_left_out)
    for (int p = 0; p < k; ++p)
      if (attitudes.lone(p)) lanes.remove(p);
  int lane_pose = choice.lane, other_height = choice.other_height;
  const int line_inside = choice.line_inside, from_picture = choice.from_picture;
  int last = k - 1;  // the pose the fit's buffers hold
  if (lane_pose >= 0) {
    // The fit's buffers hold the last pose's: look again, unless that was the lane's.
    if (lane_pose != last) {
      detection_pose_ = poses[lane_pose];
      lane = attempt(image, gyro);
      last = lane_pose;
    } else {
      lane = last_attempt;
    }
  }
  // A lane whose line inside (a row of markers that detection from a height half the
  // true one does not see) another pose's lane shows is two lanes; that one is the lane
  // (stills from a mount a quarter too low took the own left line and the next lane's
  // right line at 0.75 m, where other poses had found the lane at 1.6 m).
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

}  // namespace ccdlane
