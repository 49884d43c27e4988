// Where the processing thread sends each estimate: the LCM publisher, or a recorder in
// tests.
#pragma once

#include <cstdint>

#include "core/lane/lane_estimate.hpp"

namespace ccdlane {

class LaneSink {
 public:
  virtual ~LaneSink() = default;
  // Real-time path: no allocation. Returns false when the estimate could not be sent.
  virtual bool publish_lane(const LaneEstimate& estimate, std::int64_t capture_utime, std::int64_t publish_utime) = 0;
};

}  // namespace ccdlane
