// Whether solves set up as the options say can determine what they are asked for
// (docs/solver.md "What is and is not observable"), as a value callers decide on.
#pragma once

#include <cstdint>

#include "core/lane/lane_estimator_options.hpp"

namespace ccdlane {

enum class Observability : std::uint8_t {
  observable,
  height_unobservable,  // H free without a prior: scale is never observable from one image
  focal_unobservable,   // f free without a prior: nor is the focal length
  // phi and y0 free, no gyro reading, no roll or lane-width prior: roll about the lane
  // direction is absorbed by moving the lines sideways.
  roll_unobservable,
};

// `roll_measured`: the frames come with the gyro's reading. The daemon refuses to start
// on a configuration that is not observable, and replay on such a recording.
Observability observability(const LaneEstimatorOptions& options, bool roll_measured);

// Whether the options observe everything only with a gyro reading: a frame without one is
// then reported roll_unobservable.
bool roll_needs_gyro(const LaneEstimatorOptions& options);

// One line saying what is wrong and what to do, naming the configuration's keys; "" for
// observable.
const char* explain(Observability o);

}  // namespace ccdlane
