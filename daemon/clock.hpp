// The two clocks of the daemon: CLOCK_MONOTONIC for intervals and frame timestamps (the
// drivers' monotonic_ns / sleep_until, shared), CLOCK_REALTIME for the utime
// (microseconds since the Unix epoch) of LCM messages.
#pragma once

#include <time.h>

#include <cstdint>

#include "drivers/common/device_state.hpp"

namespace ccdlane {

inline std::int64_t realtime_us() {
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000 + ts.tv_nsec / 1000;
}

}  // namespace ccdlane
