// A GenICam camera (GigE Vision, USB3 Vision, Aravis' fake) through Aravis as a
// FrameSource: features set by name, buffers pushed before acquisition starts, frames
// popped with a timeout, bad buffers counted and requeued, and a lost camera (control
// lost, or no frames) reopened with backoff.
#pragma once

#include <atomic>
#include <cstdint>
#include <string>

#include "drivers/camera/camera_settings.hpp"
#include "drivers/camera/pixel_conversion.hpp"
#include "drivers/device_state.hpp"
#include "drivers/frame_source.hpp"

// Aravis' types, kept out of the header (glib would come with them).
typedef struct _ArvCamera ArvCamera;
typedef struct _ArvStream ArvStream;
typedef struct _ArvDevice ArvDevice;

namespace ccdlane {

class AravisCamera final : public FrameSource {
 public:
  // `id`: what arv_camera_new() takes: "Vendor-Model-Serial", a serial-bearing id, an IP
  // address (opened directly, no broadcast), or "Fake_1" (Aravis' in-process fake, whose
  // interface this enables).
  AravisCamera(std::string id, CameraSettings settings);
  ~AravisCamera() override;
  AravisCamera(const AravisCamera&) = delete;
  AravisCamera& operator=(const AravisCamera&) = delete;

  std::string open() override;
  int width() const override { return width_; }
  int height() const override { return height_; }
  // What capture() delivers: settled by the first open() (rgb8 or mono8 for 8-bit
  // capture as settings.colour and the camera decide), kept across reconnects.
  PixelFormat format() const override { return format_; }
  // Allocation-free while streaming; reopening a lost camera allocates inside Aravis.
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
  double frame_rate() const { return fps_obtained_; }
  double max_frame_rate() const { return fps_max_; }  // at the current size, as the camera says
  int packet_size() const { return packet_size_; }    // GigE Vision; 0 otherwise
  // Sets any GenICam feature by name ("ExposureTime", "Gain", "BinningHorizontal"):
  // "" or one line saying why not. Remembered and applied again after a reopen.
  std::string set_control(const std::string& name, const std::string& value);

 private:
  bool bring_up();  // opening -> configuring -> streaming; false leaves nothing open
  bool configure();
  bool set_feature(const char* name, const char* value);
  bool start_stream();
  void lose_camera(const char* why);
  void release_camera(bool camera_reachable);
  static void on_control_lost(ArvDevice* device, void* self);

  std::string id_;
  CameraSettings settings_;
  ArvCamera* camera_ = nullptr;
  ArvStream* stream_ = nullptr;
  std::atomic<bool> control_lost_{false};  // set from Aravis' heartbeat thread
  DeviceState state_ = DeviceState::closed;
  ReopenBackoff backoff_;
  ProblemText problem_;
  ProblemText notes_;
  std::string description_;

  int width_ = 0;
  int height_ = 0;
  std::uint32_t arv_format_ = 0;
  PixelFormat format_;
  bool format_locked_ = false;
  WirePixels wire_ = WirePixels::mono8;
  int significant_bits_ = 8;
  double fps_obtained_ = 0;
  double fps_max_ = 0;
  int packet_size_ = 0;
  std::size_t payload_ = 0;

  bool have_frame_id_ = false;
  std::uint64_t last_frame_id_ = 0;
  std::int64_t last_frame_ns_ = 0;
  SourceCounters counters_;
};

}  // namespace ccdlane
