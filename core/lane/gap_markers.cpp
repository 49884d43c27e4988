#include "core/lane/gap_markers.hpp"

#include <algorithm>
#include <cmath>

namespace ccdlane {

int gap_markers(std::span<const MarkCandidate> marks, std::span<const Pick> picks, const CameraModel& camera,
                const RoadLine& line, int line_index, std::span<Pick> out) {
  double nearest_row = -1.0;  // rows grow towards the car
  for (const Pick& p : picks)
    if (p.line == line_index) nearest_row = std::max(nearest_row, p.py);
  if (nearest_row < 0.0) return 0;
  // Across the road, one pixel at distance X spans X times this.
  const double mm_per_px_per_mm = camera.spec().pitch_u() / camera.pose().f_mm;
  int n = 0;
  for (const MarkCandidate& m : marks) {
    if (n == static_cast<int>(out.size())) break;
    if (m.shadow_side == 0 || !m.dot || m.joint || m.line >= 0 || m.py <= nearest_row) continue;
    const auto ground = camera.ground_point_from_pixel(Vec2(m.px(), m.py));
    if (!ground || !(ground->x() > 0.0)) continue;
    const double off_px = std::abs(ground->y() - line.y_at(ground->x())) / (ground->x() * mm_per_px_per_mm);
    if (off_px <= kGapMarkerWindowPx) out[static_cast<std::size_t>(n++)] = Pick{line_index, m.px(), m.py};
  }
  return n;
}

}  // namespace ccdlane
