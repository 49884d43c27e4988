// What the processing thread runs on each frame: detection, the gyro prior and the
// solve, behind one call (the lane estimator is adapted to this at integration).
#pragma once

#include <optional>

#include "base/gx1_angles.hpp"
#include "base/image_view.hpp"
#include "core/lane/lane_estimate.hpp"
#include "drivers/frame_source.hpp"

namespace ccdlane {

class FrameProcessor {
 public:
  virtual ~FrameProcessor() = default;

  // One frame, one estimate: ok = false with a reason when the frame gives none. Runs on
  // the real-time path: no allocation, no exceptions; every workspace was sized when the
  // processor was built. `attitude` is the gyro reading at the frame's time (the frame's
  // own recorded reading, else the live gyro's), if there is one.
  virtual LaneEstimate process(const ImageView& image, const FrameMeta& meta, std::optional<Gx1Angles> attitude) = 0;
};

}  // namespace ccdlane
