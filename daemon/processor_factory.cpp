// Every frame goes through the lane estimator; its size must be the camera's.
#include "daemon/processor_factory.hpp"

#include <stdexcept>
#include <string>

#include "daemon/lane_estimator_processor.hpp"

namespace ccdlane {

std::unique_ptr<FrameProcessor> make_frame_processor(const Config& config, const FrameSource& source) {
  if (source.width() != config.camera.Nu || source.height() != config.camera.Nv)
    throw std::runtime_error(source.describe() + ": frames are " + std::to_string(source.width()) + "x" +
                             std::to_string(source.height()) + ", camera.Nu x camera.Nv is " +
                             std::to_string(config.camera.Nu) + "x" + std::to_string(config.camera.Nv));
  return std::make_unique<LaneEstimatorProcessor>(config);
}

}  // namespace ccdlane
