// The support checks of a solved lane (lane_support.hpp).
#include "core/lane/lane_support.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <optional>
#include <utility>

#include "base/median.hpp"

namespace ccdlane {
namespace {

bool agrees(const std::optional<Prior>& prior, double value) {
  return !prior || !(std::abs(value - prior->mean) > kPriorAgreementSigmas * prior->sigma);
}

}  // namespace

const char* to_string(SupportProblem p) {
  switch (p) {
    case SupportProblem::none: return "none";
    case SupportProblem::too_few_marks: return "too_few_marks";
    case SupportProblem::too_short: return "too_short";
    case SupportProblem::out_of_range: return "out_of_range";
    case SupportProblem::not_paint: return "not_paint";
    case SupportProblem::disagrees_with_prior: return "disagrees_with_prior";
    case SupportProblem::heading_off_lane: return "heading_off_lane";
    case SupportProblem::attitude_off_mount: return "attitude_off_mount";
    case SupportProblem::implausible_motion: return "implausible_motion";
    case SupportProblem::cluttered_lane: return "cluttered_lane";
  }
  return "?";
}

LineSupport line_support(std::span<const Pick> picks, std::span<const Vec2> points_mm, int line) {
  // The nearest and farthest two: an end mark far from all others is left out.
  LineSupport s;
  double near[2] = {1e300, 1e300}, far[2] = {-1e300, -1e300};
  const std::size_t n = std::min(picks.size(), points_mm.size());
  for (std::size_t i = 0; i < n; ++i) {
    if (picks[i].line != line) continue;
    const double x = points_mm[i].x();
    ++s.marks;
    if (x < near[0]) near[1] = near[0], near[0] = x;
    else if (x < near[1]) near[1] = x;
    if (x > far[0]) far[1] = far[0], far[0] = x;
    else if (x > far[1]) far[1] = x;
  }
  if (s.marks == 0) return s;
  s.near_mm = s.marks >= 2 && near[1] - near[0] > kIsolatedMarkGapMm ? near[1] : near[0];
  s.far_mm = s.marks >= 2 && far[0] - far[1] > kIsolatedMarkGapMm ? far[1] : far[0];
  return s;
}

SupportProblem check_line_support(const LineSupport& line, const DetectionConfig& detection) {
  if (line.marks < detection.min_marks) return SupportProblem::too_few_marks;
  const double searched_mm = detection.max_range_mm - detection.min_range_mm;
  if (line.far_mm - line.near_mm < std::min(kMinLineSpanMm, 0.5 * searched_mm)) return SupportProblem::too_short;
  if (line.near_mm < detection.min_range_mm / kRangeSlack || line.far_mm > detection.max_range_mm * kRangeSlack)
    return SupportProblem::out_of_range;
  return SupportProblem::none;
}

bool check_dash_support(const LineSupport& line, const DetectionConfig& detection, const GroupingParams& grouping,
                        double lane_width_mm) {
  return lane_width_mm >= kMinDashLaneWidthMm && lane_width_mm <= kMaxDashLaneWidthMm &&
         line.marks >= grouping.min_dash_marks && line.far_mm - line.near_mm >= grouping.min_dash_span_mm &&
         line.near_mm >= detection.min_range_mm / kRangeSlack && line.far_mm <= detection.max_range_mm * kRangeSlack;
}

double paint_width_slope(std::span<const MarkCandidate> marks, int detection_line) {
  const auto counts = [&](const MarkCandidate& m) {
    return m.line == detection_line && !m.dot && m.X > 0.0 && m.width_px() > 0.0;
  };
  const auto all = static_cast<std::size_t>(std::count_if(marks.begin(), marks.end(), counts));
  if (all < 3) return std::nan("");
  std::array<std::pair<double, double>, kMaxPaintSlopeMarks> v;  // (log distance, log width)
  const std::size_t step = (all + v.size() - 1) / v.size();
  std::size_t n = 0, seen = 0;
  for (const MarkCandidate& m : marks)
    if (counts(m) && seen++ % step == 0) v[n++] = {std::log(m.X), std::log(m.width_px())};
  // Theil-Sen: the median of the slopes between every two marks at least 5 % apart in
  // distance (nearer pairs say more of edge noise than of the slope).
  std::array<double, kMaxPaintSlopeMarks*(kMaxPaintSlopeMarks - 1) / 2> slopes;
  std::size_t k = 0;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j)
      if (const double dx = v[j].first - v[i].first; std::abs(dx) > kMinPaintSlopeLogSpan)
        slopes[k++] = (v[j].second - v[i].second) / dx;
  return k == 0 ? std::nan("") : median_in_place(std::span(slopes).first(k));
}

SupportProblem check_paint_width(double slope) {
  return std::abs(slope - kPaintWidthSlope) <= kPaintWidthSlopeTolerance ? SupportProblem::none
                                                                         : SupportProblem::not_paint;
}

double paint_width_spread(std::span<const MarkCandidate> marks, int detection_line, std::span<double> scratch) {
  std::size_t n = 0;
  for (const MarkCandidate& m : marks) {
    if (n == scratch.size()) break;
    if (m.line != detection_line || m.dot || !(m.X > 0.0) || !(m.width_px() > 0.0)) continue;
    scratch[n++] = std::log(m.width_px() * m.X);
  }
  if (n < 3) return std::nan("");
  const std::span<double> v = scratch.first(n);
  const double centre = median_in_place(v);
  for (double& x : v) x = std::abs(x - centre);
  return median_in_place(v);
}

SupportProblem check_paint_width_spread(double spread, const DetectionConfig& detection) {
  const double mix = std::log(detection.max_mark_width_mm / detection.min_mark_width_mm) / 4.0;
  return spread < mix ? SupportProblem::none : SupportProblem::not_paint;
}

double judged_speed_mps(std::optional<double> measured_mps, double configured_mps, double curvature_per_m) {
  if (measured_mps) return *measured_mps;
  const double curvature = std::abs(curvature_per_m);
  if (configured_mps * configured_mps * curvature <= kMaxLateralAccelerationMps2) return configured_mps;
  // A billionth slower: at the bend's own speed the acceleration is the bound itself, which
  // rounding may put a bit above it.
  return std::max(kMinUnmeasuredSpeedMps, (1.0 - 1e-9) * std::sqrt(kMaxLateralAccelerationMps2 / curvature));
}

SupportProblem check_motion(double speed_mps, double heading_deg, double curvature_per_m) {
  const double lateral_speed = speed_mps * std::abs(std::sin(deg_to_rad(heading_deg)));
  const double lateral_acceleration = speed_mps * speed_mps * std::abs(curvature_per_m);
  return lateral_speed <= kMaxLateralSpeedMps && lateral_acceleration <= kMaxLateralAccelerationMps2
             ? SupportProblem::none
             : SupportProblem::implausible_motion;
}

bool own_line_jumped(double y0_mm, double tracked_y0_mm, double dt_s, double lane_width_mm) {
  const double moved = std::abs(y0_mm - tracked_y0_mm);
  return moved > kMaxLateralSpeedMps * 1000.0 * std::max(0.0, dt_s) + kOwnLineStepSlackMm &&
         moved < 0.5 * lane_width_mm;
}

bool yaw_jumped(double psi_deg, double tracked_psi_deg, double dt_s) {
  return std::abs(psi_deg - tracked_psi_deg) > kMaxYawRateDegPerS * std::max(0.0, dt_s) + kYawStepSlackDeg;
}

namespace {

// Whether two bars on neighbouring scan rows overlap along the row: one bar running on.
bool runs_on(const MarkCandidate& a, const MarkCandidate& b) {
  return a.left_px <= b.right_px && b.left_px <= a.right_px;
}

// For marks `inside` (indices into `marks`, in scan-row order), in `run_rows`, the scan
// rows of the longest run of overlapping bars on consecutive scan rows through each
// (from above and below, at most 255).
void measure_runs(std::span<const MarkCandidate> marks, std::span<const std::uint32_t> inside,
                  std::span<std::uint8_t> run_rows) {
  std::array<std::int16_t, kMaxClutterMarks> above{}, below{};
  const int n = static_cast<int>(inside.size());
  const auto mark = [&](int k) -> const MarkCandidate& { return marks[static_cast<std::size_t>(inside[k])]; };
  for (int k = 0; k < n; ++k) {
    above[k] = 1;
    for (int j = k - 1; j >= 0 && mark(j).scan_row >= mark(k).scan_row - 1; --j)
      if (mark(j).scan_row == mark(k).scan_row - 1 && runs_on(mark(j), mark(k)))
        above[k] = std::max<std::int16_t>(above[k], static_cast<std::int16_t>(above[j] + 1));
  }
  for (int k = n - 1; k >= 0; --k) {
    below[k] = 1;
    for (int j = k + 1; j < n && mark(j).scan_row <= mark(k).scan_row + 1; ++j)
      if (mark(j).scan_row == mark(k).scan_row + 1 && runs_on(mark(j), mark(k)))
        below[k] = std::max<std::int16_t>(below[k], static_cast<std::int16_t>(below[j] + 1));
    run_rows[k] = static_cast<std::uint8_t>(std::min(255, above[k] + below[k] - 1));
  }
}

}  // namespace

bool is_line_inside(const InsidePieces& p) {
  return p.dashes >= kMinInsideLineDashes || p.dashes + p.dots >= kMinInsideLinePieces ||
         (p.dashes + p.dots >= GroupingParams{}.min_joint_dots && p.joints >= kMinInsideJointBins);
}

namespace {

// The pieces of one line among `inside` marks (bars running on, dots, joints): sorted by
// offset from the lane's left line, a band kInsideLineBandMm wide slides across them. Its
// dashes are the separate runs of kClutterBinMm bins that each hold two or more of its
// bars; its dots and joints, the bins that hold one (the marks of one dot on
// neighbouring scan rows share one). The fullest band that makes a line, else the fullest.
InsidePieces most_pieces_in_a_band(std::span<InsideMark> inside) {
  std::sort(inside.begin(), inside.end(), [](const InsideMark& a, const InsideMark& b) { return a.offset < b.offset; });
  std::array<std::uint8_t, 64> in_bin{}, in_dot_bin{}, in_joint_bin{};
  std::uint64_t held = 0, dotted = 0, joint = 0;  // dash bins holding two or more marks; bins holding a dot, a joint
  const auto count = [](std::array<std::uint8_t, 64>& counts, std::uint64_t& mask, int at, int step, int least) {
    const auto k = static_cast<std::size_t>(std::min(63, at));
    counts[k] = static_cast<std::uint8_t>(std::min(255, counts[k] + step));
    const std::uint64_t bit = std::uint64_t{1} << k;
    mask = counts[k] >= least ? mask | bit : mask & ~bit;
  };
  const auto add = [&](const InsideMark& m, int step) {
    const int b = static_cast<int>(m.X / kClutterBinMm);
    if (m.kind == InsideMark::dot)
      count(in_dot_bin, dotted, b, step, 1);
    else if (m.kind == InsideMark::joint)
      count(in_joint_bin, joint, b, step, 1);
    else
      count(in_bin, held, b, step, 2);
  };
  const auto pieces = [](const InsidePieces& p) { return p.dashes + p.dots + p.joints; };
  InsidePieces most;
  std::size_t j = 0;
  for (std::size_t i = 0; i < inside.size(); ++i) {
    for (; j < inside.size() && inside[j].offset - inside[i].offset <= kInsideLineBandMm; ++j) add(inside[j], +1);
    const InsidePieces here{std::popcount(held & ~(held << 1)), std::popcount(dotted), std::popcount(joint)};
    if (std::pair(is_line_inside(here), pieces(here)) > std::pair(is_line_inside(most), pieces(most))) most = here;
    add(inside[i], -1);
  }
  return most;
}

}  // namespace

LaneClutter lane_clutter(std::span<const MarkCandidate> marks, const RoadLine& left, int left_line,
                         const RoadLine& right, int right_line, double margin_mm, InsidePieces* line_inside,
                         double faint_share) {
  std::uint64_t inside = 0, on_lines = 0;  // one bit per bin
  const auto bin_of = [](double X) { return std::uint64_t{1} << std::min(63, static_cast<int>(X / kClutterBinMm)); };
  std::array<std::uint32_t, kMaxClutterMarks> inside_marks{};
  std::array<InsideMark, kMaxClutterMarks> pieces;  // bars running on, dots, joints: what a line inside would be
  int num_pieces = 0;
  const auto add_piece = [&](const MarkCandidate& m, InsideMark::Kind kind) {
    if (!line_inside) return;
    // A line between two lanes lies well inside what they make; beside either line lie
    // its own shadow, a second stripe, its markers' offset from it.
    const double offset = left.y_at(m.X) - m.Y, width = left.y_at(m.X) - right.y_at(m.X);
    if (num_pieces < kMaxClutterMarks && offset >= kInsideLineFromSide * width &&
        offset <= (1.0 - kInsideLineFromSide) * width)
      pieces[static_cast<std::size_t>(num_pieces++)] = {offset, m.X, kind};
  };
  std::array<std::uint8_t, kMaxClutterMarks> run_rows{};
  int num_inside = 0;
  // The lines' marks' contrasts (the first kMaxClutterMarks), when faint marks are told.
  std::array<double, kMaxClutterMarks> line_contrast;
  std::size_t num_line_contrasts = 0;
  LaneClutter c;
  for (std::size_t i = 0; i < marks.size(); ++i) {
    const MarkCandidate& m = marks[i];
    if (!(m.X >= 0.0)) continue;
    if (m.joint && m.line < 0) {
      // A joint no line took is the road's own seam, not clutter on it; but markers set
      // along one are a line.
      add_piece(m, InsideMark::joint);
      continue;
    }
    const std::uint64_t bin = bin_of(m.X);
    if (m.line == left_line || m.line == right_line) {
      on_lines |= bin;
      ++c.line_marks;
      if (faint_share > 0.0 && num_line_contrasts < line_contrast.size())
        line_contrast[num_line_contrasts++] = m.contrast;
    } else if (m.Y < left.y_at(m.X) - margin_mm && m.Y > right.y_at(m.X) + margin_mm) {
      if (num_inside < kMaxClutterMarks) {
        inside_marks[static_cast<std::size_t>(num_inside++)] = static_cast<std::uint32_t>(i);
      } else {  // beyond the bound, counted as clutter as they come
        inside |= bin;
        ++c.inside_marks;
      }
    }
  }
  const std::span<const std::uint32_t> found(inside_marks.data(), static_cast<std::size_t>(num_inside));
  measure_runs(marks, found, run_rows);
  const double faint =
      num_line_contrasts > 0 ? faint_share * median_in_place(std::span(line_contrast).first(num_line_contrasts)) : 0.0;
  for (int k = 0; k < num_inside; ++k) {
    const MarkCandidate& m = marks[static_cast<std::size_t>(found[static_cast<std::size_t>(k)])];
    const bool stands = run_rows[static_cast<std::size_t>(k)] >= kMinStandingRows;
    const bool in_dash = run_rows[static_cast<std::size_t>(k)] >= kMinInsideDashRows;
    if (in_dash || m.dot) add_piece(m, in_dash ? InsideMark::dash : InsideMark::dot);
    if (stands) {
      ++c.standing_marks;
      continue;
    }
    if (m.contrast < faint) {
      ++c.faint_marks;
      continue;
    }
    inside |= bin_of(m.X);
    ++c.inside_marks;
  }
  if (line_inside) *line_inside = most_pieces_in_a_band(std::span(pieces).first(static_cast<std::size_t>(num_pieces)));
  c.inside_bins = std::popcount(inside);
  c.line_bins = std::popcount(on_lines);
  return c;
}

SupportProblem check_clutter(const LaneClutter& clutter) {
  // Along much of the lane and as dense as its lines: a field of bars.
  return clutter.inside_bins > kMaxClutterPerLineLength * clutter.line_bins &&
                 clutter.inside_marks > kMaxClutterMarksPerLineMark * clutter.line_marks
             ? SupportProblem::cluttered_lane
             : SupportProblem::none;
}

SupportProblem check_priors(const SolverPriors& priors, const CameraPose& pose, double lane_width_mm) {
  const bool ok = agrees(priors.psi_deg, rad_to_deg(pose.attitude.psi)) &&
                  agrees(priors.theta_deg, rad_to_deg(pose.attitude.theta)) &&
                  agrees(priors.phi_deg, rad_to_deg(pose.attitude.phi)) && agrees(priors.H_mm, pose.H_mm) &&
                  agrees(priors.f_mm, pose.f_mm) && agrees(priors.lane_width_mm, lane_width_mm);
  return ok ? SupportProblem::none : SupportProblem::disagrees_with_prior;
}

SupportProblem check_body_motion(const SolverPriors& priors, const Attitude& solved, const Attitude& mount) {
  const auto near_mount = [](const std::optional<Prior>& prior, double solved_rad, double mount_rad) {
    return prior || std::abs(rad_to_deg(solved_rad - mount_rad)) <= kMaxBodyMotionDeg;
  };
  return near_mount(priors.theta_deg, solved.theta, mount.theta) && near_mount(priors.phi_deg, solved.phi, mount.phi)
             ? SupportProblem::none
             : SupportProblem::attitude_off_mount;
}

bool spans_two_lanes(const OwnLanePlace& wide, const OwnLanePlace& narrow) {
  const double width = wide.width_mm();
  if (!(width > 0.0 && wide.H_mm > 0.0 && narrow.H_mm > 0.0)) return false;
  const double scale = wide.H_mm / narrow.H_mm;
  const double left = narrow.left_mm * scale, right = narrow.right_mm * scale;
  const auto on = [&](double a, double b) { return std::abs(a - b) <= kSharedLineShare * width; };
  const auto inside = [&](double y) {
    return y < wide.left_mm - kInsideLineFromSide * width && y > wide.right_mm + kInsideLineFromSide * width;
  };
  return (on(left, wide.left_mm) && inside(right)) || (on(right, wide.right_mm) && inside(left));
}

SupportProblem check_heading(double heading_deg) {
  return std::abs(heading_deg) <= kMaxLaneHeadingDeg ? SupportProblem::none : SupportProblem::heading_off_lane;
}

}  // namespace ccdlane
