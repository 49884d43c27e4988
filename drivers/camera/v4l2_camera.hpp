// A V4L2 (UVC, vivid, any streaming capture node) camera as a FrameSource: format
// negotiation, frame rate, controls, mmap streaming, drop counting, and recovery from
// unplug (reopen with backoff) and from stalls (stream restart).
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "drivers/camera/camera_settings.hpp"
#include "drivers/camera/pixel_conversion.hpp"
#include "drivers/camera/v4l2_device.hpp"
#include "drivers/device_state.hpp"
#include "drivers/frame_source.hpp"

struct v4l2_queryctrl;

namespace ccdlane {

class V4l2Camera final : public FrameSource {
 public:
  static constexpr int kMaxBuffers = 32;

  V4l2Camera(std::string device_path, CameraSettings settings);
  ~V4l2Camera() override;
  V4l2Camera(const V4l2Camera&) = delete;
  V4l2Camera& operator=(const V4l2Camera&) = delete;

  std::string open() override;
  int width() const override { return width_; }
  int height() const override { return height_; }
  // What capture() delivers: settled by the first open() (rgb8 or mono8 for 8-bit
  // capture as settings.colour and the device decide), kept across reopens.
  PixelFormat format() const override { return format_; }
  CaptureStatus capture(const MutableImageView& into, FrameMeta& meta, int timeout_ms) override;
  void close() override;
  std::string describe() const override { return description_; }
  std::string last_problem() const override { return problem_.str(); }
  void copy_last_problem(char* out, std::size_t size) const override {
    if (size > 0) std::snprintf(out, size, "%s", problem_.c_str());
  }
  SourceCounters counters() const override { return counters_; }

  DeviceState state() const { return state_; }
  int significant_bits() const { return significant_bits_; }
  double frame_rate() const { return fps_obtained_; }  // 0 when the device sets its own
  // Sets a control by its V4L2 name ("Gain", "Exposure Time, Absolute"; case, spaces and
  // punctuation ignored, so v4l2-ctl's "exposure_time_absolute" works too) to a number.
  // "" or one line saying why not. Remembered and applied again after a reopen.
  std::string set_control(const std::string& name, const std::string& value);

 private:
  struct Mapped {
    void* start = nullptr;
    std::size_t length = 0;
  };

  bool bring_up();  // opening -> configuring -> streaming; false leaves the device released
  bool check_capabilities();
  bool negotiate_format();
  bool set_frame_rate();
  bool apply_controls();
  bool map_buffers();
  bool start_stream();
  bool restart_stream();
  void lose_device(int neg_errno, const char* during);
  void release_device();
  bool find_control(std::uint32_t id, const char* name, v4l2_queryctrl& out) const;
  int write_control(const v4l2_queryctrl& ctrl, double value, const char* what);
  CaptureStatus dequeue(const MutableImageView& into, FrameMeta& meta);

  std::string path_;
  CameraSettings settings_;
  V4l2Device device_;
  DeviceState state_ = DeviceState::closed;
  ReopenBackoff backoff_;
  ProblemText problem_;
  ProblemText notes_;  // what was not as asked but is not fatal (no exposure control, ...)
  std::string description_;

  std::array<Mapped, kMaxBuffers> buffers_{};
  int buffer_count_ = 0;
  bool streaming_ = false;
  int width_ = 0;
  int height_ = 0;
  PixelFormat format_;
  bool format_locked_ = false;
  std::uint32_t fourcc_ = 0;
  WirePixels wire_ = WirePixels::mono8;
  int significant_bits_ = 8;
  std::ptrdiff_t bytes_per_line_ = 0;
  std::size_t size_image_ = 0;
  double fps_obtained_ = 0;
  char card_[64] = {};
  char driver_[32] = {};

  bool have_sequence_ = false;
  std::uint32_t last_sequence_ = 0;
  std::int64_t last_frame_ns_ = 0;
  SourceCounters counters_;
};

}  // namespace ccdlane
