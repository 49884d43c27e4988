// The radius as people read it: see radius_text.hpp.
#include "tools/ccdlane/radius_text.hpp"

#include <cmath>
#include <cstdio>

namespace ccdlane::cli {

std::string radius_text(double radius_m) {
  if (std::isnan(radius_m)) return "-";
  if (std::isinf(radius_m) || std::abs(radius_m) >= kStraightRadiusM) return "straight";
  char text[32];
  std::snprintf(text, sizeof text, "%.0f m", radius_m);
  return text;
}

}  // namespace ccdlane::cli
