// The lines found from less than a vote (line_grouper.hpp): parallels of the lines
// found, single dashes, the own lane's joint where no line was found on its side, and
// the lines one lane beyond the outermost ones.
#include <algorithm>
#include <cmath>

#include "core/detection/grouping_rules.hpp"
#include "core/detection/line_grouper.hpp"

namespace ccdlane {

using namespace grouping;

namespace {

// The pitch error a row of dots beside a single line may show as tilt: tracking's.
constexpr double kDotRowPitchErrorRad = GroupingParams{}.max_pitch_error_rad;
constexpr int kDashAttempts = 8;  // y0 bins tried for single dashes

// A mark's y at the reference distance along the road's line through it (twice: the
// slope depends on where the line is), the road bending with curvature c.
double reference_y(const RoadDirection& road, double c, const MarkCandidate& m) {
  const double y = m.Y + (road.through(m.Y).m + c * (kReferenceMm + m.X)) * (kReferenceMm - m.X);
  return m.Y + (road.through(y).m + c * (kReferenceMm + m.X)) * (kReferenceMm - m.X);
}

// Votes of marks for their y at the reference distance, one bin per kY0BinMm.
using ReferenceVotes = std::array<std::uint16_t, LineGrouper::kY0Bins>;

void vote_reference_y(ReferenceVotes& votes, double y) {
  const double u = (y - kY0MinMm) / kY0BinMm;
  if (u >= 0.0 && u < LineGrouper::kY0Bins) ++votes[static_cast<std::size_t>(u)];
}

// The bin whose window of three holds the most votes, among the bins whose centre y
// `allowed` takes (all when none is given); its votes (0 and bin -1 when none holds any).
template <typename Allowed>
int strongest_window(const ReferenceVotes& votes, int& bin, Allowed allowed) {
  int best = 0;
  bin = -1;
  for (int i = 1; i + 1 < LineGrouper::kY0Bins; ++i) {
    if (!allowed(kY0MinMm + (i + 0.5) * kY0BinMm)) continue;
    const int v = votes[static_cast<std::size_t>(i - 1)] + votes[static_cast<std::size_t>(i)] +
                  votes[static_cast<std::size_t>(i + 1)];
    if (v > best) best = v, bin = i;
  }
  return best;
}
int strongest_window(const ReferenceVotes& votes, int& bin) {
  return strongest_window(votes, bin, [](double) { return true; });
}

// How far beyond the outermost line found a line is looked for among them: one lane
// further, as wide as lanes are (lane_support.hpp's kMaxDashLaneWidthMm).
constexpr double kMaxLaneBeyondMm = 5000.0;

// How much more a line beyond the outermost line found may scatter than the own lane's
// (find_lines_beyond).
constexpr double kBeyondRmsScale = 1.3;

}  // namespace

bool LineGrouper::beyond_a_yellow_line(double y, int n) const {
  for (int k = 0; k < n; ++k) {
    const DetectedLine& other = found_[static_cast<std::size_t>(k)];
    const double y_other = other.fit.y_at(kReferenceMm);
    if (other.yellow && y * y_other > 0.0 && std::abs(y) > std::abs(y_other)) return true;
  }
  return false;
}

bool LineGrouper::add_parallel(std::span<MarkCandidate> marks, const GroupingParams& params, int& n,
                               const RoadLine& model, int prior_index, double beyond_y_mm) {
  const double y_ref_mm = model.y_at(kReferenceMm);
  DetectedLine l;
  // Beside one line alone, or one lane beyond the outermost line found, a row of dots may
  // run as a pitch error tilts it (see consensus_line): the road's direction there is the
  // one line's, or the lines' extrapolated beyond them, and a pitch error tilts a line in
  // proportion to its distance from those. Up to tracking's error: a search's wider one
  // would let chance rows of blobs across the lane pass. (Rows of Botts' dots one lane
  // beyond: 14 mount rows of TuSimple's stills found 83 more of 4872 labelled lines, 14
  // more false of 3567 reported.) Paint keeps the road's direction: an arrow's strokes
  // beside a dash would tilt it.
  const double from_y_mm = n == 1 ? found_[0].fit.y_at(kReferenceMm) : beyond_y_mm;
  const double tilt = std::isnan(from_y_mm)
                          ? 0.0
                          : pitch_tilt(from_y_mm, y_ref_mm, std::min(params.max_pitch_error_rad, kDotRowPitchErrorRad),
                                       params.height_mm);
  if (!fit_line(marks, model, kNewLineGateMm, n, params, l, true, tilt)) {
    release_line(marks, n);
    return false;
  }
  l.prior_index = prior_index;
  l.parallel = true;
  if (l.dots && beyond_a_yellow_line(l.fit.y_at(kReferenceMm), n)) {
    release_line(marks, n);
    return false;
  }
  return admit(marks, l, n, params);
}

int LineGrouper::find_dashes(std::span<MarkCandidate> marks, std::span<const RoadLine> priors,
                             const GroupingParams& params, int n) {
  if (n == 0) return n;
  const RoadDirection road = road_direction({found_.data(), static_cast<std::size_t>(n)}, curvature_);
  auto add_parallel = [&](double y_ref_mm, int prior_index) {
    this->add_parallel(marks, params, n, road.through(y_ref_mm), prior_index);
  };
  for (std::size_t k = 0; k < priors.size() && n < kMaxFoundLines; ++k) {
    if (!continues_prior(static_cast<int>(k), n)) add_parallel(priors[k].y_at(kReferenceMm), static_cast<int>(k));
  }
  ReferenceVotes y_votes{};
  for (const MarkCandidate& m : marks)
    if (m.line == -1) vote_reference_y(y_votes, reference_y(road, curvature_, m));
  for (int attempt = 0; attempt < kDashAttempts && n < kMaxFoundLines; ++attempt) {
    int bi = -1;
    if (strongest_window(y_votes, bi) < params.min_dash_marks) break;
    add_parallel(kY0MinMm + (bi + 0.5) * kY0BinMm, -1);
    for (int i = bi - 1; i <= bi + 1; ++i) y_votes[static_cast<std::size_t>(i)] = 0;
  }
  return n;
}

int LineGrouper::find_own_joint(std::span<MarkCandidate> marks, const GroupingParams& params, int n) {
  // Only where the own lane has a line on one side of the vehicle and none on the other.
  double left = 1e300, right = -1e300;  // the nearest line's y on each side
  for (int k = 0; k < n; ++k) {
    const double y = found_[static_cast<std::size_t>(k)].fit.y_at(kReferenceMm);
    if (y > 0.0)
      left = std::min(left, y);
    else
      right = std::max(right, y);
  }
  const bool have_left = left < 1e300;
  const bool have_right = right > -1e300;
  if (have_left == have_right || n >= kMaxFoundLines) return n;
  const double side = have_left ? -1.0 : 1.0, own = have_left ? left : right;
  const RoadDirection road = road_direction({found_.data(), static_cast<std::size_t>(n)}, curvature_);
  // The free joint pieces' y at the reference distance along the road's line through
  // each (find_dashes' vote), on the missing side, a lane's width from the line found.
  const auto on_the_missing_side = [&](double y) {
    const double width = std::abs(y - own);
    return side * y > 0.0 && width >= params.min_separation_mm && width <= kMaxLaneBeyondMm;
  };
  ReferenceVotes y_votes{};
  for (const MarkCandidate& m : marks)
    if (m.joint && m.line == -1)
      if (const double y = reference_y(road, curvature_, m); on_the_missing_side(y)) vote_reference_y(y_votes, y);
  int bi = -1;
  if (strongest_window(y_votes, bi) < params.min_marks) return n;
  const RoadLine model = road.through(kY0MinMm + (bi + 0.5) * kY0BinMm);
  DetectedLine l;
  if (!join_joint(marks, model, static_cast<std::int16_t>(n), params, params.min_span_mm, model, kNewLineGateMm, l,
                  0) ||
      beyond_a_yellow_line(l.fit.y_at(kReferenceMm), n)) {
    release_line(marks, n);
    return n;
  }
  admit(marks, l, n, params);
  return n;
}

bool LineGrouper::continues_prior(int k, int n) const {
  for (int j = 0; j < n; ++j)
    if (found_[static_cast<std::size_t>(j)].prior_index == k) return true;
  return false;
}

int LineGrouper::find_lines_beyond(std::span<MarkCandidate> marks, std::span<const RoadLine> priors,
                                   const GroupingParams& params, int n) {
  // Only beside a lane: the lines found must say where the road runs and how wide its
  // lanes are before a bar whose edges a step may have pulled counts for anything.
  if (n < 2) return n;
  for (MarkCandidate& m : marks)
    if (m.line == kHeldLine) m.line = -1;
  const RoadDirection road = road_direction({found_.data(), static_cast<std::size_t>(n)}, curvature_);
  // The outermost line on each side; but a row of dots found as a parallel of the others
  // (find_dashes) beyond another line on its side is the weakest evidence of a line there
  // is (a few blobs of a concrete's texture make one): the line beyond is looked for past
  // the line inside it, and where it is paint, it takes the dots' place (admit).
  const auto outermost_on = [&](double side) {
    double outer = 0.0, inner = 0.0;
    bool weak = false;
    for (int k = 0; k < n; ++k) {
      const DetectedLine& l = found_[static_cast<std::size_t>(k)];
      const double y = l.fit.y_at(kReferenceMm);
      if (side * y <= side * outer) {
        if (side * y > side * inner) inner = y;
        continue;
      }
      if (side * outer > side * inner) inner = outer;
      outer = y, weak = l.dots && l.parallel;
    }
    return weak && inner != 0.0 ? inner : outer;
  };
  const double leftmost = outermost_on(+1.0), rightmost = outermost_on(-1.0);
  // The free marks' y at the reference distance along the road's line through each (the
  // same vote as find_dashes'), on each side, from a lane's narrowest to its widest
  // beyond the outermost line.
  ReferenceVotes y_votes{};
  for (const MarkCandidate& m : marks) {
    if (m.line != -1) continue;
    const double y = reference_y(road, curvature_, m), beyond = std::max(y - leftmost, rightmost - y);
    if (beyond >= params.min_separation_mm && beyond <= kMaxLaneBeyondMm) vote_reference_y(y_votes, y);
  }
  // A line beyond is not held to the own lane's scatter bound (GroupingParams::max_rms_px,
  // set just below what clutter in the gate scatters): it is fitted along the road's
  // direction as the lines found give it, 3.5 m and more from them, where the pose's
  // error and a guessed distortion tilt it most, and its bars are mostly held ones, whose
  // edges the step beside them pulls. TuSimple's solid shoulder lines, plain to see,
  // scattered 1.2-1.4 px about it; bounds from 1.3 to 2 times the own lane's found the
  // same lines. What such a line needs besides: a lane beside it, the votes of a dash's
  // marks within 300 mm of one line along the road's direction, and a line's coverage.
  GroupingParams beyond_params = params;
  beyond_params.max_rms_px *= kBeyondRmsScale;
  for (const double side : {+1.0, -1.0}) {
    const double outermost = side > 0 ? leftmost : rightmost;
    // Beyond a line on that side of the vehicle only: where the lines found all lie on the
    // other side, what lies beyond is the own lane's line, which such bars never make
    // (segB's barrier foot beside a faded yellow line).
    if (side * outermost <= 0.0) continue;
    int bi = -1;
    const int best = strongest_window(y_votes, bi, [&](double y) { return side * (y - outermost) > 0.0; });
    if (best < params.min_dash_marks || n >= kMaxFoundLines) continue;
    const double y_ref = kY0MinMm + (bi + 0.5) * kY0BinMm;
    // A yellow line is the travelled way's edge: beyond it lie a shoulder and a barrier's
    // foot, no lane (segA's median barrier).
    if (beyond_a_yellow_line(y_ref, n)) continue;
    // The previous frame's line there, when no line found continues it: this one does.
    int prior_index = -1;
    for (std::size_t k = 0; k < priors.size(); ++k)
      if (!continues_prior(static_cast<int>(k), n) && std::abs(priors[k].y_at(kReferenceMm) - y_ref) <= kNewLineGateMm)
        prior_index = static_cast<int>(k);
    add_parallel(marks, beyond_params, n, road.through(y_ref), prior_index, outermost);
  }
  return n;
}

int LineGrouper::drop_dots_beyond_yellow(std::span<MarkCandidate> marks, int n) {
  std::array<bool, kMaxFoundLines> drop{};
  bool any = false;
  for (int k = 0; k < n; ++k) {
    const DetectedLine& l = found_[static_cast<std::size_t>(k)];
    any |= drop[static_cast<std::size_t>(k)] = l.dots && !l.yellow && beyond_a_yellow_line(l.fit.y_at(kReferenceMm), n);
  }
  return any ? drop_lines(marks, n, drop) : n;
}

}  // namespace ccdlane
