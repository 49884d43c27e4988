// The one-parameter division model of radial distortion and its closed-form inverse.
#pragma once

#include <optional>

#include "core/geometry/types.hpp"

namespace ccdlane {

// Observed (distorted) pixel -> ideal pixel: u = c + (d - c) / (1 + k |d - c|^2).
// Empty when 1 + k r^2 <= 0 (only possible for pincushion, k > 0): no ideal counterpart.
std::optional<Vec2> undistort_pixel(const Vec2& observed, const Vec2& centre, double k_px2);

// Ideal pixel -> observed pixel, the radial inverse of undistort_pixel. Empty when
// 4 k r_u^2 >= 1 (k > 0 only). d_observed_d_ideal, when given, receives the 2x2 Jacobian.
std::optional<Vec2> distort_pixel(const Vec2& ideal, const Vec2& centre, double k_px2,
                                  Mat2* d_observed_d_ideal = nullptr);

}  // namespace ccdlane
