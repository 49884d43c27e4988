// [gyro] device -> the AttitudeProvider that reads it ("" = no gyro).
#pragma once

#include <memory>
#include <string>

#include "app/config.hpp"
#include "app/attitude_provider.hpp"

namespace ccdlane {

// "" when this build can read [gyro] device (or none is configured), else why not.
std::string attitude_provider_unavailable(const Config& config);

// The provider, not yet opened; null when [gyro] names no device. Throws
// std::runtime_error with attitude_provider_unavailable()'s text otherwise.
std::unique_ptr<AttitudeProvider> make_attitude_provider(const Config& config);

}  // namespace ccdlane
