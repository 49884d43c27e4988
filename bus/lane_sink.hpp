// Where the processing thread sends each estimate (and, when recording is on, each frame):
// the LCM publisher, or a recorder in tests.
#pragma once

#include <cstdint>

#include "base/image_view.hpp"
#include "bus/frame_message.hpp"
#include "core/lane/lane_estimate.hpp"

namespace ccdlane {

class LaneSink {
 public:
  virtual ~LaneSink() = default;
  // Real-time path: no allocation. Returns false when the estimate could not be sent.
  virtual bool publish_lane(const LaneEstimate& estimate, std::int64_t capture_utime, std::int64_t publish_utime) = 0;

  // Whether processed frames go out too ([lcm] publish_frames), for lcm-logger to record.
  virtual bool publishes_frames() const { return false; }
  // One processed frame, under the sequence and frame time its lane message carries.
  // Real-time path: no allocation. False when it could not be sent.
  virtual bool publish_frame(const ImageView& /*image*/, const FrameRecord& /*record*/) { return false; }
};

}  // namespace ccdlane
