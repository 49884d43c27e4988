// Line grouping on the road plane. A homography maps straight image lines to straight
// road lines whatever the pose error, so lines stay straight on the road even when the
// pose used to project the marks is off; the vote spans slopes wide enough for a few
// degrees of pitch or yaw error, and the gates widen with distance for the same reason.
// Here the order of group() and the vote; one line's fit is line_grouper_fit.cpp's, the
// lines found from less than a vote line_grouper_beyond.cpp's, what they share
// grouping_rules.hpp's.
#include "core/detection/line_grouper.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>

#include "core/detection/grouping_rules.hpp"
#include "core/geometry/road_line.hpp"  // own_lane_lines

namespace ccdlane {

using namespace grouping;

namespace {

constexpr double kSlopeMin = -0.25, kSlopeStep = 0.0125;

constexpr double kPriorGateMm = 350.0;  // gate about a previous frame's line at 0 m
// A road's curvature changes slowly along it (clothoids between arcs): from one frame to
// the next a line's own curvature moves by far less than this (a 500 m radius). A fit
// that bends more has taken an arrow's, a word's or a car's strokes beside the line.
constexpr double kMaxPriorCurvatureChange = 1e-6;
constexpr int kNewLineAttempts = 16;       // voted cells tried for new lines
constexpr int kJointAttempts = 4;          // of them, cells a joint's votes made strong enough
constexpr double kCurvatureChange = 1e-8;  // a shared curvature that moved more re-casts the votes
// Paint is better evidence of a line than blobs are (a barrier's or a kerb's texture makes
// rows of blobs too): it votes twice, so that lines of paint are tried first, and a row of
// blobs beside one is then too near it to be a line of its own.
constexpr int kPaintVotes = 2;
// Of two lines of paint too near each other to be two lane lines, the first found stands
// (a previous frame's line, the most votes) unless the other has this many times its
// marks: a solid line beside a barrier's foot that a previous frame took.
constexpr int kReplacingMarks = 2;

// Whether line `l`, found after `other` and too near it, takes its place. Paint is better
// evidence than a row of blobs (a barrier's or a kerb's texture makes those too), yellow
// paint better than grey bars (barrier feet, kerbs, seams and slab edges are grey, and
// a yellow line's colour bleeds into its sides, so fewer of its bars pass the row
// filter's step test than a grey bar's do), and then the first found unless the other
// has far more marks.
bool replaces(const DetectedLine& l, const DetectedLine& other) {
  if (l.dots) return false;
  if (other.dots) return true;
  if (l.yellow != other.yellow) return l.yellow;
  return l.marks >= kReplacingMarks * other.marks;
}

// Whether line `l` runs along the road the lines found give, within what a pitch error of
// the detection pose makes of their slopes (GroupingParams::max_pitch_error_rad).
bool along_the_road(const DetectedLine& l, std::span<const DetectedLine> lines, const GroupingParams& params) {
  if (lines.empty()) return true;
  const double y = l.fit.y_at(kReferenceMm);
  const RoadDirection road = road_direction(lines, l.fit.c_per_mm);
  // Two lines or more give the road's direction with the pitch error's tilt in it (their
  // slope against y): the new line's slope is that, but for edge noise. One line alone
  // leaves the whole tilt between the two open.
  const double tilt = lines.size() == 1
                          ? pitch_tilt(lines[0].fit.y_at(kReferenceMm), y, params.max_pitch_error_rad, params.height_mm)
                          : 0.0;
  return std::abs(l.fit.m - road.through(y).m) <= 2.0 * params.slope_noise + tilt;
}

// The marks of a line that was found but refused beside a better one (the other edge of
// a double line, a seam beside a line of dots): for the rest of this frame's search they
// are neither free nor any line's. Left free, they would vote for the same line again in
// the next cells and use up the new-line attempts before the road's other lines are
// tried. group() frees them at its end.
constexpr std::int16_t kSpentLine = -2;

void spend_line(std::span<MarkCandidate> marks, int line) {
  for (MarkCandidate& m : marks)
    if (m.line == line) m.line = kSpentLine;
}

}  // namespace

double width_distance_slope(std::span<const MarkCandidate> marks, int line, bool dots) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int n = 0;
  for (const MarkCandidate& m : marks) {
    if (m.line != line || m.dot != dots || !(m.X > 0.0) || !(m.width_px() > 0.0)) continue;
    const double lx = std::log(m.X), ly = std::log(m.width_px());
    sx += lx, sy += ly, sxx += lx * lx, sxy += lx * ly;
    ++n;
  }
  if (n < 3) return std::nan("");
  const double spread = n * sxx - sx * sx;
  if (!(spread > 1e-9 * n * n)) return std::nan("");
  return (n * sxy - sx * sy) / spread;
}

LineGrouper::LineGrouper(int max_marks)
    : votes_(static_cast<std::size_t>(kY0Bins) * kSlopeBins, 0),
      joint_votes_(votes_.size(), 0),
      gated_(static_cast<std::size_t>(max_marks)) {
  // A mark votes in one y0 bin per slope (paint twice, a dot or a joint once): the sum
  // over three bins of one slope, of both accumulators, holds each mark's votes once, and
  // the search's 16-bit sums must not wrap.
  assert(kPaintVotes * max_marks <= 65535);
}

void LineGrouper::vote(const MarkCandidate& mark, int delta) {
  // The y0 bin, as a real number, falls linearly with the slope bin: no division or
  // floor per cell (truncation is the floor where the bin exists, u >= 0).
  const double u0 = (mark.Y - curvature_ * mark.X * mark.X - kSlopeMin * mark.X - kY0MinMm) / kY0BinMm;
  const double du = kSlopeStep * mark.X / kY0BinMm;
  const int weight = mark.dot || mark.joint ? 1 : kPaintVotes;
  std::vector<std::uint16_t>& votes = mark.joint ? joint_votes_ : votes_;
  if (mark.joint) joint_votes_cast_ += delta;
  for (int j = 0; j < kSlopeBins; ++j) {
    const double u = u0 - j * du;
    if (!(u >= 0.0 && u < kY0Bins)) continue;
    const int i = static_cast<int>(u);
    std::uint16_t& v = votes[static_cast<std::size_t>(i) * kSlopeBins + static_cast<std::size_t>(j)];
    v = static_cast<std::uint16_t>(delta > 0 ? std::min(v + weight, 65535) : std::max(v - weight, 0));
  }
}

bool LineGrouper::admit(std::span<MarkCandidate> marks, const DetectedLine& l, int& n, const GroupingParams& params) {
  // The lines `l` is too near to be a lane line beside; it replaces them all or none.
  std::array<bool, kMaxFoundLines> conflict{};
  bool any = false;
  for (int k = 0; k < n; ++k) {
    const DetectedLine& other = found_[static_cast<std::size_t>(k)];
    if (std::abs(other.fit.y_at(kReferenceMm) - l.fit.y_at(kReferenceMm)) >= params.min_separation_mm) continue;
    if (!replaces(l, other)) {
      spend_line(marks, n);
      return false;
    }
    conflict[static_cast<std::size_t>(k)] = any = true;
  }
  found_[static_cast<std::size_t>(n++)] = l;    // its marks are already line n's
  if (any) n = drop_lines(marks, n, conflict);  // the replaced ones
  return true;
}

int LineGrouper::drop_lines(std::span<MarkCandidate> marks, int n, const std::array<bool, kMaxFoundLines>& drop) {
  std::array<std::int16_t, kMaxFoundLines> index{};
  int kept = 0;
  for (int k = 0; k < n; ++k) {
    if (drop[static_cast<std::size_t>(k)]) {
      index[static_cast<std::size_t>(k)] = -1;
      continue;
    }
    found_[static_cast<std::size_t>(kept)] = found_[static_cast<std::size_t>(k)];
    index[static_cast<std::size_t>(k)] = static_cast<std::int16_t>(kept++);
  }
  for (MarkCandidate& m : marks)
    if (m.line >= 0 && m.line < n) m.line = index[static_cast<std::size_t>(m.line)];
  return kept;
}

int LineGrouper::continue_priors(std::span<MarkCandidate> marks, std::span<const RoadLine> priors,
                                 const GroupingParams& params) {
  // The own lane's lines first, the nearest on each side of the vehicle; the lines beyond
  // them only when both were found again. Continued without the lane, a line beyond sets
  // a slope and a curvature from its few (and held) bars that the lines found after it
  // are then looked for along (segB: the yellow line lost for a frame, the solve's yaw 2
  // degrees off); it is found again beside the lane later (find_dashes, find_lines_beyond).
  const OwnLaneLines own = own_lane_lines(priors);
  GroupingParams continuing = params;
  continuing.continuing_tracked_line = params.tracked_priors;
  int n = 0;
  for (const bool own_lane : {true, false}) {
    if (!own_lane && n < 2) break;
    for (std::size_t k = 0; k < priors.size() && n < kMaxFoundLines; ++k) {
      if ((static_cast<int>(k) == own.left || static_cast<int>(k) == own.right) != own_lane) continue;
      // By its paint, else by a slabs' joint with markers along it: fit_line takes a joint
      // only where markers are most of the marks it gates, and a joint's pieces lie on
      // every scan row (held still 3: a lane's line of 57 pieces and 3 markers, found by
      // a search's find_own_joint, lost on the next frame, which looked for it as paint).
      DetectedLine l;
      if (!fit_line(marks, priors[k], kPriorGateMm, n, continuing, l) &&
          !join_joint(marks, priors[k], static_cast<std::int16_t>(n), params, params.min_span_mm, priors[k],
                      kPriorGateMm, l, params.min_joint_dots))
        continue;
      if (std::abs(l.fit.c_per_mm - priors[k].c_per_mm) > kMaxPriorCurvatureChange) {
        release_line(marks, n);
        continue;
      }
      l.prior_index = static_cast<int>(k);
      admit(marks, l, n, params);
    }
  }
  return n;
}

double LineGrouper::shared_curvature(std::span<const RoadLine> priors, int n) const {
  double sum = 0.0, weight = 0.0;
  for (int k = 0; k < n; ++k) {
    const DetectedLine& l = found_[static_cast<std::size_t>(k)];
    // Too short to show curvature, or a row of blobs (set by hand, a few centimetres off).
    if (l.far_mm - l.near_mm < kCurvatureSpanMm || l.dots) continue;
    sum += l.fit.c_per_mm * l.marks;
    weight += l.marks;
  }
  if (weight > 0.0) return sum / weight;
  double prior_c = 0.0;
  for (const RoadLine& p : priors) prior_c += p.c_per_mm / static_cast<double>(priors.size());
  return prior_c;
}

void LineGrouper::revote(std::span<const MarkCandidate> marks) {
  std::fill(votes_.begin(), votes_.end(), 0);
  std::fill(joint_votes_.begin(), joint_votes_.end(), 0);
  joint_votes_cast_ = 0;
  for (const MarkCandidate& m : marks)
    if (m.line == -1) vote(m, +1);
}

int LineGrouper::strongest_cell(int& bi, int& bj, int min_joint_dots) const {
  // The first cell (in y0, then slope order) of the most votes over 3 bins of y0; a
  // joint's votes count where that many dots' (or paint's) are. Sums and row maxima are
  // vector operations; a row is searched only when it beats the best.
  int best = 0;
  bi = bj = -1;
  // 16-bit sums throughout (the constructor's bound: they do not wrap), which the
  // compiler vectorises; the joints' array is read only when it holds votes that count.
  const bool with_joints = joint_votes_cast_ > 0 && min_joint_dots <= 65535;
  const auto min_own = static_cast<std::uint16_t>(std::min(min_joint_dots, 65535));
  for (int i = 1; i + 1 < kY0Bins; ++i) {
    const std::uint16_t* row = votes_.data() + static_cast<std::size_t>(i) * kSlopeBins;
    const std::uint16_t* joints = joint_votes_.data() + static_cast<std::size_t>(i) * kSlopeBins;
    std::array<std::uint16_t, kSlopeBins> sums;
    for (int j = 0; j < kSlopeBins; ++j)
      sums[static_cast<std::size_t>(j)] =
          static_cast<std::uint16_t>(row[j - kSlopeBins] + row[j] + row[j + kSlopeBins]);
    if (with_joints)
      for (int j = 0; j < kSlopeBins; ++j) {
        const auto joint = static_cast<std::uint16_t>(joints[j - kSlopeBins] + joints[j] + joints[j + kSlopeBins]);
        const std::uint16_t own = sums[static_cast<std::size_t>(j)];
        sums[static_cast<std::size_t>(j)] = static_cast<std::uint16_t>(own + (own >= min_own ? joint : 0));
      }
    std::uint16_t row_best = 0;
    for (std::uint16_t v : sums) row_best = std::max(row_best, v);
    if (row_best <= best) continue;
    best = row_best;
    bi = i;
    bj = static_cast<int>(std::find(sums.begin(), sums.end(), row_best) - sums.begin());
  }
  return best;
}

int LineGrouper::strongest_cell_own_votes(int bi, int bj) const {
  int own = 0;
  for (int i = bi - 1; i <= bi + 1; ++i)
    own += votes_[static_cast<std::size_t>(i) * kSlopeBins + static_cast<std::size_t>(bj)];
  return own;
}

int LineGrouper::find_new_lines(std::span<MarkCandidate> marks, std::span<const RoadLine> priors,
                                const GroupingParams& params, int n) {
  curvature_ = shared_curvature(priors, n);
  revote(marks);
  int joint_attempts = 0;
  for (int attempt = 0; attempt < kNewLineAttempts && n < kMaxFoundLines; ++attempt) {
    int bi = -1, bj = -1;
    // Joints count towards a few cells only: every seam with a speck or two on it makes one.
    const int joint_dots = joint_attempts < kJointAttempts ? params.min_joint_dots : 1 << 20;
    if (strongest_cell(bi, bj, joint_dots) < params.min_marks) break;
    if (strongest_cell_own_votes(bi, bj) < params.min_marks) ++joint_attempts;
    const RoadLine model{kY0MinMm + (bi + 0.5) * kY0BinMm, kSlopeMin + bj * kSlopeStep, curvature_};
    DetectedLine l;
    const int before = n;
    if (fit_line(marks, model, kNewLineGateMm, n, params, l) &&
        along_the_road(l, {found_.data(), static_cast<std::size_t>(n)}, params)) {
      if (!admit(marks, l, n, params)) {  // its marks are spent: they vote no more
        revote(marks);
        continue;
      }
      const double c = shared_curvature(priors, n);
      if (std::abs(c - curvature_) > kCurvatureChange || n <= before) {  // moved, or in the place of others
        curvature_ = c;
        revote(marks);
      } else {
        for (const MarkCandidate& m : marks)
          if (m.line == n - 1) vote(m, -1);
      }
      continue;
    }
    release_line(marks, n);
    // Not a line: silence this cell and its neighbours.
    for (int i = std::max(0, bi - 1); i <= std::min(kY0Bins - 1, bi + 1); ++i)
      for (int j = std::max(0, bj - 1); j <= std::min(kSlopeBins - 1, bj + 1); ++j)
        votes_[static_cast<std::size_t>(i) * kSlopeBins + static_cast<std::size_t>(j)] =
            joint_votes_[static_cast<std::size_t>(i) * kSlopeBins + static_cast<std::size_t>(j)] = 0;
  }
  return n;
}

int LineGrouper::keep_nearest(std::span<MarkCandidate> marks, const GroupingParams& params, int n,
                              std::array<DetectedLine, kMaxDetectedLines>& out) const {
  std::array<int, kMaxFoundLines> order{};
  auto y_ref = [&](int k) { return found_[static_cast<std::size_t>(k)].fit.y_at(kReferenceMm); };
  auto insertion_sort = [&order](int count, auto before) {
    for (int i = 1; i < count; ++i)
      for (int j = i; j > 0 && before(order[static_cast<std::size_t>(j)], order[static_cast<std::size_t>(j - 1)]); --j)
        std::swap(order[static_cast<std::size_t>(j)], order[static_cast<std::size_t>(j - 1)]);
  };
  for (int k = 0; k < n; ++k) order[static_cast<std::size_t>(k)] = k;
  insertion_sort(n, [&](int a, int b) { return std::abs(y_ref(a)) < std::abs(y_ref(b)); });
  const int kept = std::min({n, params.max_lines, kMaxDetectedLines});
  insertion_sort(kept, [&](int a, int b) { return y_ref(a) > y_ref(b); });
  std::array<std::int16_t, kMaxFoundLines> new_index{};
  new_index.fill(-1);
  out = {};
  for (int k = 0; k < kept; ++k) {
    out[static_cast<std::size_t>(k)] = found_[static_cast<std::size_t>(order[static_cast<std::size_t>(k)])];
    new_index[static_cast<std::size_t>(order[static_cast<std::size_t>(k)])] = static_cast<std::int16_t>(k);
  }
  for (MarkCandidate& m : marks)
    if (m.line >= 0) m.line = new_index[static_cast<std::size_t>(m.line)];
  return kept;
}

int LineGrouper::group(std::span<MarkCandidate> marks, std::span<const RoadLine> priors, const GroupingParams& params,
                       std::array<DetectedLine, kMaxDetectedLines>& out) {
  for (MarkCandidate& m : marks) m.line = m.for_lines_beyond ? kHeldLine : -1;
  // 1. Where the previous frame's lines were.
  int n = continue_priors(marks, priors, params);
  // 2. New lines among what is left: the strongest (y0, m) cell, fitted, until none has
  // enough votes. Lane lines share their curvature: votes are cast along the curvature
  // of the lines found so far (a dashed line on a bend is found along the solid one).
  n = find_new_lines(marks, priors, params, n);
  // 3. Single dashes: on a bend, with 3 m dashes and 9 m gaps, often one dash of a dashed
  // line is in the searched range, too little to fit a line's slope. The lines of one road
  // are parallel: such a line has the road's curvature and the slope the lines found give
  // at its y0, and only its y0 is fitted. First where the previous frame's lines that were
  // not found again were, then wherever free marks agree on one y0.
  n = find_dashes(marks, priors, params, n);
  for (MarkCandidate& m : marks)
    if (m.line == kSpentLine) m.line = -1;
  // 4. The own lane's line on the side where none was found, where concrete slabs' joint
  // runs a lane's width from the line found and no markers are seen along it: lanes are
  // slabs wide, and their lines are set along the joints (TuSimple labels them so).
  n = find_own_joint(marks, params, n);
  // 5. The lines beyond the outermost ones found, one lane further on each side, where
  // the bars of only such a line count too: an edge line beside a shoulder of another
  // surface has a step beside it all along (lane_marks.hpp, for_lines_beyond).
  n = find_lines_beyond(marks, priors, params, n);
  // The yellow edge line's rule for every row of dots, whichever step found it (the
  // steps above apply it to the rows of dots they find from a few; segA's barrier foot,
  // blobs of concrete, made a line of its own from the vote, then continued it).
  n = drop_dots_beyond_yellow(marks, n);
  // 6. Keep the lines nearest the vehicle, ordered left to right (insertion sorts: n <= 8).
  return keep_nearest(marks, params, n, out);
}

}  // namespace ccdlane
