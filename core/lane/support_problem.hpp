// Why lines that were found are not a lane: the support checks' verdicts (lane_support.hpp
// names the constants), on their own so that the estimate can carry one.
#pragma once

#include <cstdint>

namespace ccdlane {

enum class SupportProblem : std::uint8_t {
  none,
  too_few_marks,         // fewer than detection's min_marks
  too_short,             // the marks cover less road than kMinLineSpanMm
  out_of_range,          // marks solved far outside the searched range
  not_paint,             // the marks do not narrow with distance as paint does
  disagrees_with_prior,  // the solve is more than kPriorAgreementSigmas from a prior
  heading_off_lane,      // the lane crosses the vehicle's heading by more than kMaxLaneHeadingDeg
  attitude_off_mount,    // pitch or roll without a prior more than kMaxBodyMotionDeg off the mounting
  implausible_motion,    // a lateral speed or acceleration beyond kMaxLateralSpeedMps, kMaxLateralAccelerationMps2,
                         // or an own line or the yaw that jumped from where it was tracked
                         // (own_line_jumped, yaw_jumped)
  cluttered_lane,        // marks inside the lane along more of it than kMaxClutterPerLineLength of its lines' length
};
const char* to_string(SupportProblem p);

}  // namespace ccdlane
