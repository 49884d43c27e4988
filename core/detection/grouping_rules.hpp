// What line grouping's parts share (line_grouper.cpp, line_grouper_fit.cpp,
// line_grouper_beyond.cpp): the vote's bins and reference distance, the gates about a
// line looked for, the road's direction the lines found give, and the states of a
// mark's line index that are no line.
#pragma once

#include <cmath>
#include <cstdint>
#include <span>

#include "core/detection/lane_marks.hpp"
#include "core/detection/line_grouper.hpp"

namespace ccdlane::grouping {

inline constexpr double kY0MinMm = -15000.0, kY0BinMm = 100.0;
inline constexpr double kReferenceMm = 10000.0;  // where lines are compared and ordered
inline constexpr double kGateGrowth = 0.02;      // gate widening per mm of distance (pose error)
inline constexpr double kNewLineGateMm = 400.0;  // about a voted or parallel line: less known
// A line's own curvature is fitted only from marks this far apart, and this many: nearer
// ones keep the road's (shared, or the prior's).
inline constexpr double kCurvatureSpanMm = 15000.0;
inline constexpr double kMinSlopeVariance = 1e6;  // mm^2 of the lines' y spread to fit slope against y

inline double gate(double base_mm, double X) { return base_mm + kGateGrowth * X; }

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

inline RoadDirection road_direction(std::span<const DetectedLine> lines, double curvature) {
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
inline double pitch_tilt(double y_a, double y_b, double pitch_error_rad, double height_mm) {
  return std::abs(y_a - y_b) * std::tan(pitch_error_rad) / height_mm;
}

inline void release_line(std::span<MarkCandidate> marks, int line) {
  for (MarkCandidate& m : marks)
    if (m.line == line) m.line = -1;
}

// The marks only a line beyond the road's others may take (MarkCandidate::for_lines_beyond):
// neither free nor any line's until find_lines_beyond.
inline constexpr std::int16_t kHeldLine = -3;

}  // namespace ccdlane::grouping
