// Road lines projected into the picture through the camera model.
#include "tools/ccdlane/road_line_picture.hpp"

namespace ccdlane::cli {

std::optional<Vec2> road_line_pixel(const CameraModel& camera, const RoadLine& line, double x_mm) {
  return camera.pixel_from_point(Vec3(x_mm, line.y_at(x_mm), 0.0));
}

namespace {

// The first distance in (near_mm, far_mm] whose point projects, where near_mm's does not
// and far_mm's does. A pincushion lens (k_px2 > 0) has no observed pixel for a point
// beyond the edge of its field; along a line ahead, points come into it and stay (they
// only near the vanishing point), so it is found by halving.
double first_projected_mm(const CameraModel& camera, const RoadLine& line, double near_mm, double far_mm) {
  double lo = near_mm, hi = far_mm;  // lo does not project, hi does
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    (road_line_pixel(camera, line, mid) ? hi : lo) = mid;
  }
  return hi;
}

}  // namespace

std::vector<std::optional<Vec2>> road_line_pixels(const CameraModel& camera, const RoadLine& line, double near_mm,
                                                  double far_mm, int samples) {
  std::vector<std::optional<Vec2>> out;
  out.reserve(static_cast<std::size_t>(samples) + 1);
  for (int i = 0; i <= samples; ++i)
    out.push_back(road_line_pixel(camera, line, near_mm + (far_mm - near_mm) * i / samples));
  return out;
}

std::optional<double> road_line_column_at_row(const CameraModel& camera, const RoadLine& line, double row_px,
                                              double near_mm, double far_mm) {
  const auto far = road_line_pixel(camera, line, far_mm);
  if (!far) return std::nullopt;
  auto near = road_line_pixel(camera, line, near_mm);
  if (!near) {
    near_mm = first_projected_mm(camera, line, near_mm, far_mm);
    near = road_line_pixel(camera, line, near_mm);
    if (!near) return std::nullopt;
  }
  const double near_side = near->y() - row_px;
  if (near_side * (far->y() - row_px) > 0.0) return std::nullopt;
  double lo = near_mm, hi = far_mm;
  // 60 halvings bring even a 300 m span below a micrometre.
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    const auto p = road_line_pixel(camera, line, mid);
    if (!p) return std::nullopt;
    ((p->y() - row_px) * near_side > 0.0 ? lo : hi) = mid;
  }
  const auto p = road_line_pixel(camera, line, 0.5 * (lo + hi));
  if (!p) return std::nullopt;
  return p->x();
}

}  // namespace ccdlane::cli
