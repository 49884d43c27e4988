// Where a synthetic frame's truth puts a lane line in the picture, computed with the
// camera model alone (independent of the renderer and of detection).
#pragma once

#include <optional>

#include "core/geometry/camera_model.hpp"
#include "core/synth/synth_drive.hpp"

namespace ccdlane::test {

// The column (1-based, observed) where the centre line of road line j of frame f crosses
// pixel row py, by bisection on the distance ahead between near_mm and far_mm. Empty
// when the line does not cross that row there.
inline std::optional<double> truth_column(const CameraModel& cam, const SynthFrame& f, int j, double py,
                                          double near_mm = 2000.0, double far_mm = 80000.0) {
  auto pixel_at = [&](double X) {
    return cam.pixel_from_point(Vec3(X, f.y0_mm[static_cast<std::size_t>(j)] + f.c_per_mm * X * X, 0.0));
  };
  double lo = near_mm, hi = far_mm;
  const auto plo = pixel_at(lo), phi = pixel_at(hi);
  if (!plo || !phi || (plo->y() - py) * (phi->y() - py) > 0) return std::nullopt;
  for (int it = 0; it < 80; ++it) {
    const double mid = 0.5 * (lo + hi);
    const auto p = pixel_at(mid);
    if (!p) return std::nullopt;
    if ((p->y() - py) * (plo->y() - py) > 0)
      lo = mid;
    else
      hi = mid;
  }
  return pixel_at(0.5 * (lo + hi))->x();
}

}  // namespace ccdlane::test
