// Time to line crossing: the first root of a quadratic, in the form that stays accurate
// when the acceleration is tiny (no 1/a).
#include "core/ldw/tlc.hpp"

#include <cmath>

namespace ccdlane::ldw {

std::optional<double> time_to_line_crossing(double dlc_m, double approach_mps, double approach_accel_mps2) {
  if (!(approach_mps > 0.0)) return std::nullopt;
  if (dlc_m <= 0.0) return 0.0;
  const double discriminant = approach_mps * approach_mps + 2.0 * approach_accel_mps2 * dlc_m;
  if (discriminant < 0.0) return std::nullopt;  // turns back before the line
  // t = (-v + sqrt(v^2 + 2 a d)) / a, rationalised.
  return 2.0 * dlc_m / (approach_mps + std::sqrt(discriminant));
}

}  // namespace ccdlane::ldw
