// [gyro] device -> the AttitudeProvider that reads it ("" = no gyro).
#pragma once

#include <memory>
#include <string>

#include "app/attitude_provider.hpp"
#include "app/config.hpp"
#include "base/log.hpp"

namespace ccdlane {

// The provider, not yet opened; null when [gyro] names no device. Its event lines go to
// `log`, or to the process log when empty.
std::unique_ptr<AttitudeProvider> make_attitude_provider(const Config& config, const LogSink& log = {});

}  // namespace ccdlane
