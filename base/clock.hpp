// The two clocks of ccdlane: CLOCK_MONOTONIC for intervals and frame timestamps,
// CLOCK_REALTIME for the utime (microseconds since the Unix epoch) of LCM messages.
#pragma once

#include <time.h>

#include <cerrno>
#include <cstdint>

namespace ccdlane {

inline std::int64_t monotonic_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return std::int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
}

inline void sleep_until(std::int64_t t_ns) {
  timespec ts{static_cast<time_t>(t_ns / 1'000'000'000), static_cast<long>(t_ns % 1'000'000'000)};
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
  }
}

// A paced source's wait: sleeps until `due_ns` when that comes within `timeout_ms` and
// says true; otherwise sleeps out the whole timeout (a caller's timeout is a promise to
// wait that long) and says false.
inline bool sleep_until_due(std::int64_t due_ns, int timeout_ms) {
  const std::int64_t deadline = monotonic_ns() + std::int64_t{timeout_ms > 0 ? timeout_ms : 0} * 1'000'000;
  if (due_ns > deadline) {
    sleep_until(deadline);
    return false;
  }
  sleep_until(due_ns);
  return true;
}

inline std::int64_t realtime_us() {
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000 + ts.tv_nsec / 1000;
}

// The wall-clock time (utime) of an instant measured on CLOCK_MONOTONIC, such as a
// frame's capture: now on the wall clock, less how long ago it was.
inline std::int64_t realtime_us_of_monotonic(std::int64_t monotonic_t_ns) {
  return realtime_us() - (monotonic_ns() - monotonic_t_ns) / 1000;
}

}  // namespace ccdlane
