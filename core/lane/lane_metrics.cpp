// Lane metrics from the solved lines.
#include "core/lane/lane_metrics.hpp"

#include <cmath>

#include "core/geometry/types.hpp"

namespace ccdlane {

LaneMetrics lane_metrics(std::span<const EstimatedLine> lines, double psi_deg, double mount_psi_deg,
                         double departure_mm) {
  LaneMetrics out;
  const OwnLaneLines own = own_lane_lines(lines);
  out.left = own.left;
  out.right = own.right;
  double slope = 0.0, c = 0.0;
  int sides = 0;
  for (const int k : {out.left, out.right})
    if (k >= 0)
      slope += lines[static_cast<std::size_t>(k)].m, c += lines[static_cast<std::size_t>(k)].c_per_mm, ++sides;
  if (sides > 0) slope /= sides, c /= sides;
  out.heading_deg = psi_deg - mount_psi_deg - rad_to_deg(std::atan(slope));
  out.curvature_per_m = 1000.0 * 2.0 * c / std::pow(1.0 + slope * slope, 1.5);
  if (out.left < 0 || out.right < 0) return out;
  const double yl = lines[static_cast<std::size_t>(out.left)].y0_mm,
               yr = lines[static_cast<std::size_t>(out.right)].y0_mm;
  // Lines farther apart than any lane: one in between was missed; nearer: not a lane.
  out.has_lane = yl - yr >= kMinLaneWidthMm && yl - yr <= kMaxLaneWidthMm;
  if (!out.has_lane) return out;
  out.lane_width_mm = yl - yr;
  out.lateral_offset_mm = -(yl + yr) / 2.0;
  const bool near_left = yl < departure_mm, near_right = -yr < departure_mm;
  if (near_left && (!near_right || yl <= -yr))
    out.departure = Departure::left;
  else if (near_right)
    out.departure = Departure::right;
  return out;
}

}  // namespace ccdlane
