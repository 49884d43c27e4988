// What the V4L2 and Aravis capture() calls share before they wait for a frame: the check
// of the caller's buffer and the non-streaming states of the bring-up state machine.
#pragma once

#include <cstdint>
#include <optional>

#include "base/image_view.hpp"
#include "drivers/device_state.hpp"
#include "drivers/frame_source.hpp"

namespace ccdlane {

// A buffer of another size or format than the stream is a caller's bug, but on the
// capture path it is reported and counted rather than asserted.
inline bool capture_buffer_fits(const MutableImageView& into, int width, int height, PixelFormat format,
                                const char* kind, const char* device, ProblemText& problem, SourceCounters& counters) {
  if (into.data != nullptr && into.width == width && into.height == height && into.format == format) return true;
  problem.set("%s:%s: capture into a %dx%d buffer, the stream is %dx%d", kind, device, into.width, into.height, width,
              height);
  ++counters.errors;
  return false;
}

// Refuses a device that is not open; while recovering, reopens with backoff until
// `deadline_ns`. Empty once the device streams (the caller then waits for a frame),
// otherwise the status capture() returns now.
template <class BringUp>
std::optional<CaptureStatus> settle_capture_state(DeviceState& state, ReopenBackoff& backoff, std::int64_t deadline_ns,
                                                  const char* kind, const char* device, ProblemText& problem,
                                                  SourceCounters& counters, BringUp&& bring_up) {
  for (;;) {
    switch (state) {
      case DeviceState::closed:
      case DeviceState::opening:
      case DeviceState::configuring: problem.set("%s:%s: not open", kind, device); return CaptureStatus::error;
      case DeviceState::recovering:
        if (!reopen_until(backoff, deadline_ns, [&] {
              if (bring_up()) return true;
              state = DeviceState::recovering;
              return false;
            }))
          return CaptureStatus::recovering;
        ++counters.reconnects;
        continue;
      case DeviceState::streaming: return std::nullopt;
    }
  }
}

}  // namespace ccdlane
