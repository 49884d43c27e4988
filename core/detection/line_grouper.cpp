// Line grouping on the road plane. A homography maps straight image lines to straight
// road lines whatever the pose error, so lines stay straight on the road even when the
// pose used to project the marks is off; the vote spans slopes wide enough for a few
// degrees of pitch or yaw error, and the gates widen with distance for the same reason.
#include "core/detection/line_grouper.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>

#include <Eigen/Cholesky>

#include "core/geometry/road_line.hpp"  // own_lane_lines

namespace ccdlane {
namespace {

constexpr double kY0MinMm = -15000.0, kY0BinMm = 100.0;
constexpr double kSlopeMin = -0.25, kSlopeStep = 0.0125;
constexpr double kReferenceMm = 10000.0;  // where lines are compared and ordered
constexpr double kGateGrowth = 0.02;      // gate widening per mm of distance (pose error)
constexpr double kMaxCurvature = 1e-5;    // c of a 50 m radius: anything sharper is not a lane

constexpr double kPriorGateMm = 350.0;  // gate about a previous frame's line at 0 m
// A road's curvature changes slowly along it (clothoids between arcs): from one frame to
// the next a line's own curvature moves by far less than this (a 500 m radius). A fit
// that bends more has taken an arrow's, a word's or a car's strokes beside the line.
constexpr double kMaxPriorCurvatureChange = 1e-6;
constexpr double kNewLineGateMm = 400.0;  // about a voted or parallel line: less known
// A line's own curvature is fitted only from marks this far apart, and this many: nearer
// ones keep the road's (shared, or the prior's).
constexpr double kCurvatureSpanMm = 15000.0;
constexpr int kCurvatureMarks = 15;
// RANSAC samples: marks this far apart along the road for a line (two) or a parabola (three).
constexpr double kMinPairSpanMm = 2000.0;
constexpr double kMinTripleSpanMm = 3000.0;
// The pitch error a row of dots beside a single line may show as tilt: tracking's.
constexpr double kDotRowPitchErrorRad = GroupingParams{}.max_pitch_error_rad;
constexpr int kMaxPairedDots = 32;           // dot marks paired for such a row's slope
constexpr double kConsensusTolerance = 1.5;  // pixel tolerances: the consensus, and the first pass of the fit
constexpr int kFitPasses = 4;
constexpr int kNewLineAttempts = 16;       // voted cells tried for new lines
constexpr int kJointAttempts = 4;          // of them, cells a joint's votes made strong enough
constexpr int kDashAttempts = 8;           // y0 bins tried for single dashes
constexpr double kCurvatureChange = 1e-8;  // a shared curvature that moved more re-casts the votes
constexpr double kMinSlopeVariance = 1e6;  // mm^2 of the lines' y spread to fit slope against y
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

double gate(double base_mm, double X) { return base_mm + kGateGrowth * X; }

// Whether `fit` keeps within the gate about the line it was looked for along (a previous
// frame's line, a voted cell, the road's direction) over the road its marks span. A
// line's marks and an arrow's, a word's or a car's strokes beside it, each within the
// gate somewhere, fit a slanted line through both that leaves it; the line itself, once
// fitted, reaches beyond the gate only where it goes on along it.
bool stays_in_gate(const RoadLine& fit, const RoadLine& looked_for, double gate_base_mm, double near_mm,
                   double far_mm) {
  for (const double X : {near_mm, far_mm})
    if (std::abs(fit.y_at(X) - looked_for.y_at(X)) > gate(gate_base_mm, X)) return false;
  return true;
}

// Raised markers are set by hand and a dot's rows are chords of a small disc with its
// own shadow: their centres scatter a few centimetres about the line, more than paint's
// edges do near the camera, where a pixel is a few millimetres.
constexpr double kDotScatterMm = 40.0;
// Raised markers on concrete are set beside the joint between slabs, not on its seal:
// their centres 10-15 cm off it (a round marker's radius and a few centimetres; square
// ceramic ones, wider, up to 15 cm), scattered as above. 120 mm cut off the farther
// half of them (TuSimple stills 29, 39, 71: square markers, no line), 150-200 mm found
// 6-9 more lines of 348.
constexpr double kJointBandMm = 150.0;
constexpr double kMinJointCoverage = 0.4;
// A joint's pieces scatter about its fit by what the joint is on the road (its seal's
// edges, the slabs' chipped corners, the row filter's centroid of a dark line one or
// two centimetres wide), which a camera with more pixels across the same view sees over
// more pixels, not straighter. Its fit tolerance and scatter bound are the fit's pixels
// at the focal length they were set at (TuSimple's and the Udacity camera's, 1150-1200
// px), or the camera's own where those are larger. The development stills resized to
// 1.5 times their pixels had joints scattering 1.25-1.32 of their pixels (0.83-0.88 of
// the recorded pictures'), refused by the 1.1 bound; their rows of markers were drawn
// from a few far markers, off their labels at the car (docs/real-roads.md, "1920x1080").
constexpr double kJointToleranceFocalPx = 1150.0;

// The lateral road distance one pixel of the fit tolerance spans at a mark: more for a
// dot of a row of dots (`dot_line`), and for a joint's piece never less than at
// kJointToleranceFocalPx. A paint line holds the blobs beside it (its dash ends) to
// paint's tolerance, or they would pull its fit off its near paint.
double mm_per_tolerance_px(const GroupingParams& params, const MarkCandidate& m, bool dot_line) {
  const double paint = params.mm_per_px_per_mm * m.X;
  if (m.joint) return std::max(paint, m.X / kJointToleranceFocalPx);
  return m.dot && dot_line ? std::max(paint, kDotScatterMm / params.fit_tolerance_px) : paint;
}

// The lateral road distance the fit tolerance spans at a mark.
double pixel_tolerance_mm(const GroupingParams& params, const MarkCandidate& m, bool dot_line) {
  return params.fit_tolerance_px * mm_per_tolerance_px(params, m, dot_line);
}

// The road's line through a given y at the reference distance: the lines found give its
// curvature and its slope, fitted as a linear function of y when two or more lines are
// known (a pitch error tilts projected lines in proportion to their offset).
struct RoadDirection {
  double sw = 0, sy = 0, sm = 0, slope_per_mm = 0, c = 0;

  RoadLine through(double y_ref_mm) const {
    const double m = sm / sw + slope_per_mm * (y_ref_mm - sy / sw);
    return RoadLine{y_ref_mm - (m + c * kReferenceMm) * kReferenceMm, m, c};
  }
};

RoadDirection road_direction(std::span<const DetectedLine> lines, double curvature) {
  RoadDirection d;
  d.c = curvature;
  double syy = 0, sym = 0;
  for (const DetectedLine& l : lines) {
    const double w = l.marks, y = l.fit.y_at(kReferenceMm);
    d.sw += w, d.sy += w * y, d.sm += w * l.fit.m, syy += w * y * y, sym += w * y * l.fit.m;
  }
  const double var = syy / d.sw - (d.sy / d.sw) * (d.sy / d.sw);
  d.slope_per_mm = lines.size() >= 2 && var > kMinSlopeVariance ? (sym / d.sw - d.sy / d.sw * d.sm / d.sw) / var : 0.0;
  return d;
}

// How much the slopes of two lines at y_a and y_b (at the reference distance) may differ
// on the road as a detection pose `height_mm` high projects them: a pitch error up to
// `pitch_error_rad` tilts each in proportion to its offset.
double pitch_tilt(double y_a, double y_b, double pitch_error_rad, double height_mm) {
  return std::abs(y_a - y_b) * std::tan(pitch_error_rad) / height_mm;
}

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

// The straight line through marks a and b with curvature c.
RoadLine line_through(const MarkCandidate& a, const MarkCandidate& b, double c) {
  const double m = ((b.Y - c * b.X * b.X) - (a.Y - c * a.X * a.X)) / (b.X - a.X);
  return {a.Y - c * a.X * a.X - m * a.X, m, c};
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

// Whether the dots of line `line` narrow with distance as things of one size on the road
// do (width in pixels about 1 / distance): blobs along a streak on the windscreen, a pole's
// shadow or a car's edge keep their width.
constexpr double kDotWidthSlope = -1.0, kDotWidthSlopeTolerance = 0.5;
bool narrows_with_distance(std::span<const MarkCandidate> marks, int line) {
  return std::abs(width_distance_slope(marks, line, true) - kDotWidthSlope) <= kDotWidthSlopeTolerance;
}

// Separate dots among the marks of a line, taken in row order (far to near): a dot that
// starts below the rows the last one was lit over is another.
struct SeparateDots {
  int count = 0;
  int last_bottom = -1;
  void add(const MarkCandidate& m) {
    if (!m.dot || m.dot_top <= last_bottom) return;
    ++count;
    last_bottom = m.dot_bottom;
  }
};

// Where a joint is worn, filled or hidden, its line goes on through its dots: from each
// of the joint's ends [near_mm, far_mm], dot to dot, while no gap is wider than
// kMaxDotGapMm. A blob on the joint's line far beyond (a car's light, a marker of another
// stretch) is no continuation of it.
constexpr double kMaxDotGapMm = 10000.0;
void reach_through_dots(std::span<const MarkCandidate> marks, int line, double& near_mm, double& far_mm) {
  for (bool moved = true; moved;) {
    moved = false;
    for (const MarkCandidate& m : marks) {
      if (m.line != line || !m.dot) continue;
      if (m.X > far_mm && m.X - far_mm <= kMaxDotGapMm) far_mm = m.X, moved = true;
      if (m.X < near_mm && near_mm - m.X <= kMaxDotGapMm) near_mm = m.X, moved = true;
    }
  }
}

void release_line(std::span<MarkCandidate> marks, int line) {
  for (MarkCandidate& m : marks)
    if (m.line == line) m.line = -1;
}

// The marks of a line that was found but refused beside a better one (the other edge of
// a double line, a seam beside a line of dots): for the rest of this frame's search they
// are neither free nor any line's. Left free, they would vote for the same line again in
// the next cells and use up the new-line attempts before the road's other lines are
// tried. group() frees them at its end.
constexpr std::int16_t kSpentLine = -2;

// The marks only a line beyond the road's others may take (MarkCandidate::for_lines_beyond):
// neither free nor any line's until find_lines_beyond.
constexpr std::int16_t kHeldLine = -3;

// How far beyond the outermost line found a line is looked for among them: one lane
// further, as wide as lanes are (lane_support.hpp's kMaxDashLaneWidthMm).
constexpr double kMaxLaneBeyondMm = 5000.0;

// How much more a line beyond the outermost line found may scatter than the own lane's
// (find_lines_beyond).
constexpr double kBeyondRmsScale = 1.3;

// A tracked frame's line continued from the previous frame's (continue_priors) that
// scatters more than the bound about its fit is still paint, up to this much more, when
// it misses the fit smoothly: its residuals along the road (marks in scan-row order)
// correlated from one mark to the next by kSmoothMisfitCorrelation or more, over
// kSmoothMisfitMarks marks or more. Clutter spread over the tolerance band scatters
// independently (a correlation about 0, within 1 / sqrt(n)); a line of paint that the
// road's parabola bends a little differently from (a road not quite flat, a bend's
// changing curvature) misses it along a smooth curve. On the drives the yellow edge
// lines so refused read 0.61-0.92, the rows of reflectors on the median barrier -0.32 to
// 0.39. Only for a line the previous frame had: founding a line, the bound stands
// (docs/real-roads.md, "segA's one frame not ok": the stills lost by it).
constexpr double kSmoothMisfitRmsScale = 1.3;
constexpr double kSmoothMisfitCorrelation = 0.6;
constexpr int kSmoothMisfitMarks = 20;

// The lag-1 correlation of line `id`'s residuals about `model` (in tolerance pixels,
// less their mean), over its marks in the order they lie in: scan row by scan row.
double residual_correlation(std::span<const MarkCandidate> marks, std::int16_t id, const RoadLine& model,
                            const GroupingParams& params, bool dot_line, double mean_px) {
  double sum2 = 0.0, lagged = 0.0, previous = 0.0;
  bool first = true;
  for (const MarkCandidate& m : marks) {
    if (m.line != id) continue;
    const double r = (m.Y - model.y_at(m.X)) / mm_per_tolerance_px(params, m, dot_line) - mean_px;
    sum2 += r * r;
    if (!first) lagged += r * previous;
    previous = r, first = false;
  }
  return sum2 > 0.0 ? lagged / sum2 : 0.0;
}

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

int LineGrouper::gate_marks(std::span<const MarkCandidate> marks, const RoadLine& model, double gate_base_mm,
                            std::int16_t id) {
  int g = 0;
  for (std::size_t i = 0; i < marks.size() && g < static_cast<int>(gated_.size()); ++i) {
    const MarkCandidate& m = marks[i];
    if (!m.joint && (m.line == -1 || m.line == id) && std::abs(m.Y - model.y_at(m.X)) <= gate(gate_base_mm, m.X))
      gated_[static_cast<std::size_t>(g++)] = static_cast<int>(i);
  }
  return g;
}

RoadLine LineGrouper::consensus_line(std::span<const MarkCandidate> marks, int g, const RoadLine& model, int line,
                                     const GroupingParams& params, bool parallel, double slope_freedom) const {
  const auto gated = [&](int k) -> const MarkCandidate& {
    return marks[static_cast<std::size_t>(gated_[static_cast<std::size_t>(k)])];
  };
  // Each mark within the tolerance counts its contrast: a faint scar of old paint or a tar
  // seam along a dashed line has more marks than the near dash it runs beside (it lies on
  // every scan row between the dashes), and paint has several times its contrast. Counted
  // alike, the scar and the far dash made the line, 20 cm off the near dash (segA's
  // lane width 5 % short for three frames).
  auto consensus = [&](const RoadLine& h) {
    double count = 0.0;
    for (int k = 0; k < g; ++k) {
      const MarkCandidate& m = gated(k);
      if (std::abs(m.Y - h.y_at(m.X)) <= kConsensusTolerance * pixel_tolerance_mm(params, m, true)) count += m.contrast;
    }
    return count;
  };
  RoadLine best = model;
  double best_count = consensus(model);
  if (parallel) {
    // Slope and curvature are the road's: the consensus is over y0 alone, one hypothesis
    // through each gated mark.
    for (int k = 0; k < g; ++k) {
      const MarkCandidate& a = gated(k);
      RoadLine h = model;
      h.y0_mm = a.Y - (model.m + model.c_per_mm * a.X) * a.X;
      const double count = consensus(h);
      if (count > best_count) best_count = count, best = h;
    }
    // Beside one line alone, the road's slope here is that line's give or take the tilt a
    // pitch error makes over the distance between them: a row of dots a few metres long
    // would lose its near or far dots to it. Lines through two dots far enough apart, within
    // that tilt, are hypotheses too: of the first kMaxPairedDots dots in the gate (a row of
    // dots has a few marks a dot).
    std::array<int, kMaxPairedDots> dots{};
    int num_dots = 0;
    for (int k = 0; k < g && slope_freedom > 0.0 && num_dots < kMaxPairedDots; ++k)
      if (gated(k).dot) dots[static_cast<std::size_t>(num_dots++)] = k;
    for (int i = 0; i < num_dots; ++i)
      for (int k = i + 1; k < num_dots; ++k) {
        const MarkCandidate &a = gated(dots[static_cast<std::size_t>(i)]),
                            &b = gated(dots[static_cast<std::size_t>(k)]);
        if (std::abs(a.X - b.X) < kMinPairSpanMm) continue;
        const RoadLine h = line_through(a, b, model.c_per_mm);
        if (std::abs(h.m - model.m) > slope_freedom) continue;
        const double count = consensus(h);
        if (count > best_count) best_count = count, best = h;
      }
  }
  std::uint32_t state = 2654435761u * static_cast<std::uint32_t>(line + 1);  // deterministic samples
  auto next = [&state, g] {
    state = state * 1664525u + 1013904223u;
    return static_cast<int>((state >> 8) % static_cast<std::uint32_t>(g));
  };
  for (int it = 0; it < (parallel ? 0 : kRansacIterations); ++it) {
    // Straight lines through two marks (with the model's curvature) and, on a curving
    // road, parabolas through three.
    const MarkCandidate& a = gated(next());
    const MarkCandidate& b = gated(next());
    RoadLine h;
    if (it % 2 == 0) {
      if (std::abs(a.X - b.X) < kMinPairSpanMm) continue;
      h = line_through(a, b, model.c_per_mm);
    } else {
      const MarkCandidate& d = gated(next());
      if (std::abs(a.X - b.X) < kMinTripleSpanMm || std::abs(b.X - d.X) < kMinTripleSpanMm ||
          std::abs(a.X - d.X) < kMinTripleSpanMm)
        continue;
      // Divided differences through (a, b, d).
      const double ab = (b.Y - a.Y) / (b.X - a.X), bd = (d.Y - b.Y) / (d.X - b.X);
      const double c = (bd - ab) / (d.X - a.X);
      if (std::abs(c) > kMaxCurvature) continue;
      const double m = ab - c * (a.X + b.X);
      h = {a.Y - m * a.X - c * a.X * a.X, m, c};
    }
    const double count = consensus(h);
    if (count > best_count) best_count = count, best = h;
  }
  return best;
}

LineGrouper::FitPass LineGrouper::fit_pass(std::span<MarkCandidate> marks, RoadLine& model, std::int16_t id,
                                           const GroupingParams& params, double tolerance, bool parallel, bool dot_line,
                                           double road_c_per_mm) {
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  FitPass p;
  int first_row = 1 << 30, last_row = -1;
  SeparateDots dots;
  for (MarkCandidate& m : marks) {
    if (m.joint || (m.line != -1 && m.line != id)) continue;  // joints: join_joint's
    const double tol = tolerance * pixel_tolerance_mm(params, m, dot_line);
    if (std::abs(m.Y - model.y_at(m.X)) > tol) {
      m.line = -1;
      continue;
    }
    m.line = id;
    const double x = m.X * 1e-3;  // metres along, for conditioning
    const Eigen::Vector3d phi(1.0, x, x * x);
    A += phi * phi.transpose();
    b += phi * m.Y;
    ++p.marks;
    p.near_mm = std::min(p.near_mm, m.X);
    p.far_mm = std::max(p.far_mm, m.X);
    p.dot_marks += m.dot;
    p.yellow_marks += m.yellow;
    dots.add(m);
    first_row = std::min<int>(first_row, m.scan_row);
    last_row = std::max<int>(last_row, m.scan_row);
  }
  p.dots = dots.count;
  p.rows = last_row - first_row + 1;
  // The curvature term only when the marks reach far enough to show it; otherwise the
  // road's curvature is kept: y - c x^2 = y0 + m x. Not necessarily the model's: after
  // the consensus that may be a parabola through three marks a few metres apart, whose
  // curvature says little (held still 12: a row of dots 9 m long kept one of a 120 m
  // bend beside a straight road's lines, and no solve converged on it).
  Eigen::Vector3d coef = Eigen::Vector3d::Zero();
  if (p.marks == 0) return p;
  if (parallel && 2 * p.dot_marks > p.marks && p.far_mm - p.near_mm >= kOwnSlopeSpanMm) {
    // Found along the road's direction, but long enough to show its own: the direction
    // the lines found give is only as good as the pose (a pitch error tilts lines in
    // proportion to their offset, and one line alone says nothing of it), and a row of
    // dots 9 m long was 45 mm off it at its near end.
    coef[2] = model.c_per_mm * 1e6;
    coef.head<2>() = A.topLeftCorner<2, 2>().ldlt().solve(b.head<2>() - A.topRightCorner<2, 1>() * coef[2]);
  } else if (parallel) {  // y - m x - c x^2 = y0
    coef[1] = model.m * 1e3;
    coef[2] = model.c_per_mm * 1e6;
    coef[0] = (b[0] - A(0, 1) * coef[1] - A(0, 2) * coef[2]) / A(0, 0);
  } else if (p.marks >= kCurvatureMarks && p.far_mm - p.near_mm >= kCurvatureSpanMm) {
    coef = A.ldlt().solve(b);
  } else {
    coef[2] = road_c_per_mm * 1e6;
    coef.head<2>() = A.topLeftCorner<2, 2>().ldlt().solve(b.head<2>() - A.topRightCorner<2, 1>() * coef[2]);
  }
  p.finite = coef.allFinite();
  if (p.finite) model = {coef[0], coef[1] * 1e-3, coef[2] * 1e-6};
  return p;
}

bool LineGrouper::fit_line(std::span<MarkCandidate> marks, RoadLine model, double gate_base_mm, int line,
                           const GroupingParams& params, DetectedLine& out, bool parallel, double slope_freedom) {
  const auto id = static_cast<std::int16_t>(line);
  const auto release = [&] {
    release_line(marks, id);
    return false;
  };
  // 1. The free marks within the gate around the model.
  const int g = gate_marks(marks, model, gate_base_mm, id);
  const int min_marks = parallel ? params.min_dash_marks : params.min_marks;
  const double min_span_mm = parallel ? params.min_dash_span_mm : params.min_span_mm;
  if (g < min_marks) {  // too few for a line; unless dots beside a joint
    int gated_dots = 0;
    for (int k = 0; k < g; ++k) gated_dots += marks[static_cast<std::size_t>(gated_[static_cast<std::size_t>(k)])].dot;
    if (parallel || gated_dots < params.min_joint_dots) return release();
  }

  // 2. RANSAC among them: the model, or a straight line through two gated marks, that
  // has the most gated marks' contrast within a few pixels. Clutter inside a wide gate
  // would pull a plain least-squares fit off the line; the consensus does not care about it.
  const RoadLine looked_for = model;
  model = consensus_line(marks, g, model, line, params, parallel, slope_freedom);

  // 3. Least squares on the consensus, then more passes on every free mark within the
  // pixel tolerance of the fit (the line may reach beyond the gate once it is known).
  bool dot_line = true;  // until the first pass says which kind the line's marks mostly are
  for (int pass = 0; pass < kFitPasses; ++pass) {
    // The road's curvature, for a line too short to show its own: a tracked frame's is the
    // previous frame's, solved from every line. A search knows none yet (its lines found
    // so far say it, and at first nothing): a line on a bend keeps its consensus's, which
    // holds its marks (forced to the lines found so far, the stills lost 4 % of own lines).
    const double road_c = params.tracked_priors ? looked_for.c_per_mm : model.c_per_mm;
    const FitPass p =
        fit_pass(marks, model, id, params, pass == 0 ? kConsensusTolerance : 1.0, parallel, dot_line, road_c);
    const int n = p.marks;
    // Too few, or sparse (clutter, not paint), for a line of its own; unless it is a row of
    // dots (beside a joint, with fewer).
    const bool too_few =
        n < min_marks || p.far_mm - p.near_mm < min_span_mm ||
        (n < params.min_coverage * p.rows && p.dots < (parallel ? params.min_parallel_dots : params.min_dots));
    if (too_few) {
      if (2 * p.dot_marks > n && p.dots >= params.min_joint_dots && !parallel &&
          join_joint(marks, model, id, params, min_span_mm, looked_for, gate_base_mm, out, params.min_joint_dots))
        return true;
      return release();
    }
    if (!p.finite) return release();
    double sum2 = 0.0, sum2_px = 0.0, sum_px = 0.0;
    for (const MarkCandidate& m : marks) {
      if (m.line != id) continue;
      const double r = m.Y - model.y_at(m.X);
      sum2 += r * r;
      const double mm_per_px = mm_per_tolerance_px(params, m, dot_line);
      sum2_px += r * r / (mm_per_px * mm_per_px);
      sum_px += r / mm_per_px;
    }
    out.fit = model;
    out.marks = n;
    out.near_mm = p.near_mm;
    out.far_mm = p.far_mm;
    out.rms_mm = std::sqrt(sum2 / n);
    out.dots = dot_line = 2 * p.dot_marks > n;
    out.yellow = 2 * p.yellow_marks > n;
    const double rms_px = std::sqrt(sum2_px / n);
    if (pass == kFitPasses - 1 && rms_px > params.max_rms_px) {
      const bool smooth_misfit =
          params.continuing_tracked_line && n >= kSmoothMisfitMarks &&
          rms_px <= kSmoothMisfitRmsScale * params.max_rms_px &&
          residual_correlation(marks, id, model, params, dot_line, sum_px / n) >= kSmoothMisfitCorrelation;
      if (!smooth_misfit) return release();
    }
    if (pass == kFitPasses - 1 && out.dots && !narrows_with_distance(marks, id)) return release();
    if (pass == kFitPasses - 1 && !stays_in_gate(model, looked_for, gate_base_mm, p.near_mm, p.far_mm))
      return release();
  }
  return true;
}

bool LineGrouper::join_joint(std::span<MarkCandidate> marks, RoadLine model, std::int16_t id,
                             const GroupingParams& params, double min_span_mm, const RoadLine& looked_for,
                             double gate_base_mm, DetectedLine& out, int min_dots) {
  // The joint: its pieces within the band about the dots' line, then within the fit's
  // tolerance of the line they make (straight, with the road's curvature, as a joint is
  // over the reach of a few dots).
  const double c = model.c_per_mm;
  RoadLine joint = model;
  int n = 0, first_row = 1 << 30, last_row = -1;
  double near_mm = 0.0, far_mm = 0.0, sum2_px = 0.0;
  for (int pass = 0; pass < kFitPasses; ++pass) {
    double sw = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
    n = 0;
    first_row = 1 << 30, last_row = -1;
    near_mm = 1e300, far_mm = 0.0;
    for (const MarkCandidate& m : marks) {
      if (!m.joint || m.line != -1) continue;
      const double tol =
          pass == 0 ? kJointBandMm + pixel_tolerance_mm(params, m, false) : pixel_tolerance_mm(params, m, false);
      if (std::abs(m.Y - joint.y_at(m.X)) > tol) continue;
      const double x = m.X * 1e-3, y = m.Y - c * m.X * m.X;
      sw += 1, sx += x, sy += y, sxx += x * x, sxy += x * y;
      ++n;
      near_mm = std::min(near_mm, m.X);
      far_mm = std::max(far_mm, m.X);
      first_row = std::min<int>(first_row, m.scan_row);
      last_row = std::max<int>(last_row, m.scan_row);
    }
    const double det = sw * sxx - sx * sx;
    if (n < params.min_marks || far_mm - near_mm < min_span_mm || !(det > 0.0)) return false;
    const double slope = (sw * sxy - sx * sy) / det;  // per metre
    joint = {(sy - slope * sx) / sw, slope * 1e-3, c};
  }
  // Continuous, as a joint is: on most of the scan rows it spans. Chance alignments of
  // specks and cracks (a frame of noise makes a few) are on a fifth to a third of theirs.
  if (n < kMinJointCoverage * (last_row - first_row + 1)) return false;
  // Its pieces: free, within the fit's tolerance of the joint as fitted.
  const auto piece = [&](const MarkCandidate& m) {
    return m.joint && m.line == -1 && std::abs(m.Y - joint.y_at(m.X)) <= pixel_tolerance_mm(params, m, false);
  };
  double sum2_mm = 0.0;
  for (const MarkCandidate& m : marks) {
    if (!piece(m)) continue;
    const double r = m.Y - joint.y_at(m.X), r_px = r / mm_per_tolerance_px(params, m, false);
    sum2_mm += r * r;
    sum2_px += r_px * r_px;
  }
  if (std::sqrt(sum2_px / n) > params.max_rms_px || !stays_in_gate(joint, looked_for, gate_base_mm, near_mm, far_mm))
    return false;
  // The dots beside it.
  SeparateDots dots;
  int dot_marks = 0;
  for (const MarkCandidate& m : marks)
    if ((m.line == -1 || m.line == id) && m.dot && std::abs(m.Y - joint.y_at(m.X)) <= kJointBandMm) {
      ++dot_marks;
      dots.add(m);
    }
  if (dots.count < min_dots) return false;
  for (MarkCandidate& m : marks) {
    if (m.line == id) m.line = -1;
    const bool dot = m.dot && m.line == -1 && std::abs(m.Y - joint.y_at(m.X)) <= kJointBandMm;
    if (piece(m) || dot) m.line = id;
  }
  if (dots.count > 0 && !narrows_with_distance(marks, id)) {
    release_line(marks, id);
    return false;
  }
  reach_through_dots(marks, id, near_mm, far_mm);
  out.fit = joint;
  out.marks = n + dot_marks;
  out.near_mm = near_mm;
  out.far_mm = far_mm;
  out.rms_mm = std::sqrt(sum2_mm / n);  // the joint's pieces'; its dots lie off it
  out.dots = dots.count > 0;
  out.joints = n;
  out.yellow = false;
  return true;
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
