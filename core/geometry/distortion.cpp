// Division-model distortion. The inverse is written as 2 / (1 + sqrt(1 - 4 k r^2)), the
// cancellation-free form of docs/geometry.md's (1 - sqrt(1 - 4 k r^2)) / (2 k r^2): it needs no
// special case at k = 0 or r = 0 and keeps full precision for tiny k r^2.
#include "core/geometry/distortion.hpp"

#include <cmath>

namespace ccdlane {

std::optional<Vec2> undistort_pixel(const Vec2& observed, const Vec2& centre, double k_px2) {
  const Vec2 v = observed - centre;
  const double denom = 1.0 + k_px2 * v.squaredNorm();
  if (!(denom > 0.0)) return std::nullopt;
  return Vec2(centre + v / denom);
}

std::optional<Vec2> distort_pixel(const Vec2& ideal, const Vec2& centre, double k_px2, Mat2* d_observed_d_ideal) {
  const Vec2 v = ideal - centre;
  const double rho = v.squaredNorm();
  const double disc = 1.0 - 4.0 * k_px2 * rho;
  // disc == 0 is the edge of the field: its derivative is infinite, so reject it too.
  if (!(disc > 0.0)) return std::nullopt;
  const double s = std::sqrt(disc);
  const double gain = 2.0 / (1.0 + s);  // r_d / r_u
  if (d_observed_d_ideal) {
    const double dgain_drho = 4.0 * k_px2 / (s * (1.0 + s) * (1.0 + s));
    *d_observed_d_ideal = gain * Mat2::Identity() + 2.0 * dgain_drho * v * v.transpose();
  }
  return Vec2(centre + gain * v);
}

}  // namespace ccdlane
