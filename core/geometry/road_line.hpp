// A lane line on the road, y = y0 + m x + c x^2 (fixed frame, mm): the one type the
// solver solves, detection looks along, the tracker follows and the configuration seeds.
#pragma once

namespace ccdlane {

struct RoadLine {
  double y0_mm = 0.0;
  double m = 0.0;
  double c_per_mm = 0.0;

  double y_at(double x_mm) const { return y0_mm + (m + c_per_mm * x_mm) * x_mm; }
  bool operator==(const RoadLine&) const = default;
};

}  // namespace ccdlane
