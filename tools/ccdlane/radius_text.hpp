// How a lane's radius of curvature is said to a person (ccdlane monitor, the annotated
// video's strip, the drive report): a radius only where the road visibly bends.
#pragma once

#include <string>

namespace ccdlane::cli {

// Beyond this a radius is noise on a straight road ("radius -885327 m"): said "straight".
// tools/report/ccdlane_report.py applies the same bound.
inline constexpr double kStraightRadiusM = 10'000.0;

// "850 m" (signed: positive bends left), "straight" when |R| >= kStraightRadiusM or
// infinite, "-" when nothing was solved (NaN).
std::string radius_text(double radius_m);

}  // namespace ccdlane::cli
