// [gyro] device -> the AttitudeProvider that reads it ("" = no gyro).
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "app/attitude_provider.hpp"
#include "app/config.hpp"
#include "base/log.hpp"

namespace ccdlane {

// The provider, not yet opened; null when [gyro] names no device. Its event lines go to
// `log`, or to the process log when empty. `open_cancelled`, when given, is asked while
// open() waits for a sensor that does not answer: true gives up (a stop during start-up).
std::unique_ptr<AttitudeProvider> make_attitude_provider(const Config& config, const LogSink& log = {},
                                                         std::function<bool()> open_cancelled = {});

}  // namespace ccdlane
