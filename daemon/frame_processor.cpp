// The estimator is built for the configured camera: the source must deliver its size.
#include "daemon/frame_processor.hpp"

#include <stdexcept>
#include <string>

namespace ccdlane {
namespace {

const Config& with_source_size(const Config& config, const FrameSource& source) {
  if (source.width() != config.camera.Nu || source.height() != config.camera.Nv)
    throw std::runtime_error(source.describe() + ": frames are " + std::to_string(source.width()) + "x" +
                             std::to_string(source.height()) + ", camera.Nu x camera.Nv is " +
                             std::to_string(config.camera.Nu) + "x" + std::to_string(config.camera.Nv));
  return config;
}

LaneEstimatorOptions estimator_options(const Config& config, const OnlineCalibration* calibration) {
  LaneEstimatorOptions options = config.estimator_options();
  if (calibration) calibration->configure(options);
  return options;
}

}  // namespace

EstimatorProcessor::EstimatorProcessor(const Config& config, const FrameSource& source, OnlineCalibration* calibration)
    : estimator_(estimator_options(with_source_size(config, source), calibration)), calibration_(calibration) {}

}  // namespace ccdlane
