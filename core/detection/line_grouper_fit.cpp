// Fitting one line (line_grouper.hpp): the marks within the gate about the line looked
// for, their consensus, the passes that refit it to the marks within the pixels'
// tolerance, and a concrete joint with the raised markers set along it.
#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>

#include "core/detection/grouping_rules.hpp"
#include "core/detection/line_grouper.hpp"

namespace ccdlane {

using namespace grouping;

namespace {

constexpr double kMaxCurvature = 1e-5;  // c of a 50 m radius: anything sharper is not a lane
constexpr int kCurvatureMarks = 15;
// RANSAC samples: marks this far apart along the road for a line (two) or a parabola (three).
constexpr double kMinPairSpanMm = 2000.0;
constexpr double kMinTripleSpanMm = 3000.0;
constexpr int kMaxPairedDots = 32;           // dot marks paired for such a row's slope
constexpr double kConsensusTolerance = 1.5;  // pixel tolerances: the consensus, and the first pass of the fit
constexpr int kFitPasses = 4;

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

// The straight line through marks a and b with curvature c.
RoadLine line_through(const MarkCandidate& a, const MarkCandidate& b, double c) {
  const double m = ((b.Y - c * b.X * b.X) - (a.Y - c * a.X * a.X)) / (b.X - a.X);
  return {a.Y - c * a.X * a.X - m * a.X, m, c};
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

}  // namespace

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
  // Blobs beside the joint that do not narrow with distance as things of one size do are
  // not markers: the line is then a car's edge or a streak with lights on it, not a
  // joint. One or two blobs say nothing of that (their widths give no slope): a row of
  // markers that takes the joint (min_dots) is then no line, a joint alone is one without them.
  if (dots.count > 0 && !narrows_with_distance(marks, id)) {
    if (min_dots > 0 || !std::isnan(width_distance_slope(marks, id, true))) {
      release_line(marks, id);
      return false;
    }
    for (MarkCandidate& m : marks)
      if (m.line == id && m.dot) m.line = -1;
    dots = {};
    dot_marks = 0;
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

}  // namespace ccdlane
