// The capture loop both camera drivers run; see streaming_camera.hpp.
#include "drivers/camera/streaming_camera.hpp"

#include <algorithm>
#include <utility>

#include "base/clock.hpp"

namespace ccdlane {
namespace {

// 8-bit capture keeps colour only when asked; a deep mono stream stays mono16.
PixelFormat initial_format(const CameraSettings& s) {
  if (s.format == PixelFormat::mono16) return PixelFormat::mono16;
  return s.colour == ColourCapture::colour ? PixelFormat::rgb8 : PixelFormat::mono8;
}

}  // namespace

StreamingCamera::StreamingCamera(const char* kind, std::string name, CameraSettings settings)
    : kind_(kind), name_(std::move(name)), settings_(std::move(settings)), format_(initial_format(settings_)) {
  backoff_.configure(settings_.reopen_min_ms, settings_.reopen_max_ms);
}

CaptureStatus StreamingCamera::capture(const MutableImageView& into, FrameMeta& meta, int timeout_ms) {
  // A buffer of another size or format than the stream is a caller's bug, but on the
  // capture path it is reported and counted rather than asserted.
  if (into.data == nullptr || into.width != width_ || into.height != height_ || into.format != format_) {
    problem_.set("%s:%s: capture into a %dx%d buffer, the stream is %dx%d", kind_, name_.c_str(), into.width,
                 into.height, width_, height_);
    ++counters_.errors;
    return CaptureStatus::error;
  }
  const std::int64_t deadline = monotonic_ns() + std::int64_t{timeout_ms > 0 ? timeout_ms : 0} * 1'000'000;
  const std::int64_t stall_ns = std::int64_t{settings_.effective_stall_timeout_ms()} * 1'000'000;
  for (;;) {
    switch (state_) {
      case DeviceState::closed:
      case DeviceState::opening:
      case DeviceState::configuring: problem_.set("%s:%s: not open", kind_, name_.c_str()); return CaptureStatus::error;
      case DeviceState::recovering:
        if (!reopen_until(backoff_, deadline, [this] {
              if (bring_up()) return true;
              state_ = DeviceState::recovering;
              return false;
            }))
          return CaptureStatus::recovering;
        ++counters_.reconnects;
        continue;
      case DeviceState::streaming: break;
    }
    const std::int64_t now = monotonic_ns();
    if (now - last_frame_ns_ > stall_ns) {
      on_stall();
      continue;
    }
    // Wake for the stall check even when the caller would wait longer.
    const std::int64_t wake = std::min(deadline, last_frame_ns_ + stall_ns + 1'000'000);
    if (const auto status = wait_for_frame(into, meta, now, wake)) return *status;
    if (state_ != DeviceState::streaming) continue;
    if (monotonic_ns() >= deadline) {
      ++counters_.timeouts;
      return CaptureStatus::timeout;
    }
  }
}

}  // namespace ccdlane
