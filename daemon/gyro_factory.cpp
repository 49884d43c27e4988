// No gyro reader is built in yet: a configured device is refused with a clear line
// rather than silently ignored.
#include "daemon/gyro_factory.hpp"

#include <stdexcept>

namespace ccdlane {

std::string attitude_provider_unavailable(const Config& config) {
  if (config.gyro.device.empty()) return "";
  return "gyro.device: \"" + config.gyro.device + "\": the 3DM-GX1 reader is not available in this build of ccdlaned";
}

std::unique_ptr<AttitudeProvider> make_attitude_provider(const Config& config) {
  if (config.gyro.device.empty()) return nullptr;
  throw std::runtime_error(attitude_provider_unavailable(config));
}

}  // namespace ccdlane
