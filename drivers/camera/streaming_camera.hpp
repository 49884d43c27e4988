// What the V4L2 and Aravis cameras share: the state a streaming camera keeps (size,
// format, counters, the problem text, the bring-up state and its reopen backoff) and the
// shape of capture() — check the caller's buffer, settle the bring-up state, restart or
// reopen on a stall, wait for a frame until the deadline. Each driver supplies the calls
// that touch its device.
#pragma once

#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>

#include "drivers/camera/camera_settings.hpp"
#include "drivers/camera/pixel_conversion.hpp"
#include "drivers/device_state.hpp"
#include "drivers/frame_source.hpp"

namespace ccdlane {

class StreamingCamera : public FrameSource {
 public:
  int width() const override { return width_; }
  int height() const override { return height_; }
  // What capture() delivers: settled by the first open() (rgb8 or mono8 for 8-bit
  // capture as settings.colour and the device decide), kept across reopens.
  PixelFormat format() const override { return format_; }
  // Allocation-free while streaming (reopening a lost device may allocate in the driver's
  // library). Never blocks past `timeout_ms`.
  CaptureStatus capture(const MutableImageView& into, FrameMeta& meta, int timeout_ms) final;
  std::string describe() const override { return description_; }
  std::string last_problem() const override { return problem_.str(); }
  void copy_last_problem(char* out, std::size_t size) const override {
    if (size > 0) std::snprintf(out, size, "%s", problem_.c_str());
  }
  SourceCounters counters() const override { return counters_; }

  DeviceState state() const { return state_; }
  int significant_bits() const { return significant_bits_; }
  double frame_rate() const { return fps_obtained_; }  // 0 when the device sets its own

 protected:
  // `kind` ("v4l2", "aravis") and `name` (device path, camera id) prefix every problem.
  StreamingCamera(const char* kind, std::string name, CameraSettings settings);

  // opening -> configuring -> streaming; false leaves the device released (state
  // recovering or closed, as the driver decides).
  virtual bool bring_up() = 0;
  // No frame for the stall timeout while streaming: restart the stream or drop the device.
  virtual void on_stall() = 0;
  // Waits until `wake_ns` at the latest for one frame and converts it into `into`: the
  // status to return, or nothing when none came (or the device was lost: the state then
  // says so and capture() settles it).
  virtual std::optional<CaptureStatus> wait_for_frame(const MutableImageView& into, FrameMeta& meta,
                                                      std::int64_t now_ns, std::int64_t wake_ns) = 0;

  // Counts a delivered frame as a frame or an error, as it is.
  CaptureStatus counted(CaptureStatus status) {
    if (status == CaptureStatus::frame)
      ++counters_.frames;
    else
      ++counters_.errors;
    return status;
  }

  const char* kind_;
  std::string name_;
  CameraSettings settings_;
  DeviceState state_ = DeviceState::closed;
  ReopenBackoff backoff_;
  ProblemText problem_;
  ProblemText notes_;  // what was not as asked but is not fatal (no exposure control, ...)
  std::string description_;

  int width_ = 0;
  int height_ = 0;
  PixelFormat format_;
  bool format_locked_ = false;
  WirePixels wire_ = WirePixels::mono8;
  int significant_bits_ = 8;
  double fps_obtained_ = 0;
  std::int64_t last_frame_ns_ = 0;
  SourceCounters counters_;
};

}  // namespace ccdlane
