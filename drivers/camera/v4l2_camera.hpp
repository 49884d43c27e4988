// A V4L2 (UVC, vivid, any streaming capture node) camera as a FrameSource: format
// negotiation, frame rate, controls, mmap streaming, drop counting, and recovery from
// unplug (reopen with backoff) and from stalls (stream restart).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include "drivers/camera/streaming_camera.hpp"
#include "drivers/camera/v4l2_device.hpp"

struct v4l2_queryctrl;

namespace ccdlane {

class V4l2Camera final : public StreamingCamera {
 public:
  static constexpr int kMaxBuffers = 32;

  V4l2Camera(std::string device_path, CameraSettings settings);
  ~V4l2Camera() override;
  V4l2Camera(const V4l2Camera&) = delete;
  V4l2Camera& operator=(const V4l2Camera&) = delete;

  std::string open() override;
  void close() override;

  // Sets a control by its V4L2 name ("Gain", "Exposure Time, Absolute"; case, spaces and
  // punctuation ignored, so v4l2-ctl's "exposure_time_absolute" works too) to a number.
  // "" or one line saying why not. Remembered and applied again after a reopen.
  std::string set_control(const std::string& name, const std::string& value);

 private:
  struct Mapped {
    void* start = nullptr;
    std::size_t length = 0;
  };

  bool bring_up() override;
  void on_stall() override;
  std::optional<CaptureStatus> wait_for_frame(const MutableImageView& into, FrameMeta& meta, std::int64_t now_ns,
                                              std::int64_t wake_ns) override;
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

  V4l2Device device_;
  std::array<Mapped, kMaxBuffers> buffers_{};
  int buffer_count_ = 0;
  bool streaming_ = false;
  std::uint32_t fourcc_ = 0;
  std::ptrdiff_t bytes_per_line_ = 0;
  std::size_t size_image_ = 0;
  char card_[64] = {};
  char driver_[32] = {};

  bool have_sequence_ = false;
  std::uint32_t last_sequence_ = 0;
};

}  // namespace ccdlane
