// Where a road line y = y0 + m x + c x^2 lies in the picture at a camera pose: what the
// overlays draw and what `ccdlane score` compares with annotations, computed one way.
#pragma once

#include <optional>
#include <vector>

#include "core/detection/lane_marks.hpp"
#include "core/geometry/camera_model.hpp"

namespace ccdlane::cli {

// The line's point x_mm ahead as an observed (distorted) 1-based pixel; empty when it
// is not in front of the lens or beyond the distortion model's field.
std::optional<Vec2> road_line_pixel(const CameraModel& camera, const RoadLine& line, double x_mm);

// The line from near_mm to far_mm ahead, sampled at `samples` + 1 evenly spaced
// distances, as observed (distorted) 1-based pixels; empty entries where a point is not
// in front of the lens.
std::vector<std::optional<Vec2>> road_line_pixels(const CameraModel& camera, const RoadLine& line, double near_mm,
                                                  double far_mm, int samples);

// The 1-based column at which the line crosses 1-based picture row `row_px`, somewhere
// between near_mm and far_mm ahead; empty when it does not (the row is above where the
// line ends or below where it starts). Bisection on the distance: on the road ahead, a
// point's row falls monotonically as it gets farther. Through a pincushion lens the line
// starts where its points come into the lens's field, when near_mm's lie beyond it.
std::optional<double> road_line_column_at_row(const CameraModel& camera, const RoadLine& line, double row_px,
                                              double near_mm, double far_mm);

}  // namespace ccdlane::cli
