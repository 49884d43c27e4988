// A lane line on the road, y = y0 + m x + c x^2 (fixed frame, mm): the one type the
// solver solves, detection looks along, the tracker follows and the configuration seeds.
#pragma once

#include <cstddef>
#include <span>

namespace ccdlane {

struct RoadLine {
  double y0_mm = 0.0;
  double m = 0.0;
  double c_per_mm = 0.0;

  double y_at(double x_mm) const { return y0_mm + (m + c_per_mm * x_mm) * x_mm; }
  bool operator==(const RoadLine&) const = default;
};

// The own lane's lines among `lines` (anything with a y0_mm): the nearest with y0 > 0
// (left) and the nearest with y0 <= 0 (right); -1 where a side has none.
struct OwnLaneLines {
  int left = -1, right = -1;
};
template <typename Line>
OwnLaneLines own_lane_lines(std::span<const Line> lines) {
  OwnLaneLines own;
  for (std::size_t j = 0; j < lines.size(); ++j) {
    const double y0 = lines[j].y0_mm;
    if (y0 > 0.0 && (own.left < 0 || y0 < lines[static_cast<std::size_t>(own.left)].y0_mm))
      own.left = static_cast<int>(j);
    if (y0 <= 0.0 && (own.right < 0 || y0 > lines[static_cast<std::size_t>(own.right)].y0_mm))
      own.right = static_cast<int>(j);
  }
  return own;
}

}  // namespace ccdlane
