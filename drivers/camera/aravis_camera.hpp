// A GenICam camera (GigE Vision, USB3 Vision, Aravis' fake) through Aravis as a
// FrameSource: features set by name, buffers pushed before acquisition starts, frames
// popped with a timeout, bad buffers counted and requeued, and a lost camera (control
// lost, or no frames) reopened with backoff.
#pragma once

#include <atomic>
#include <cstdint>
#include <optional>
#include <string>

#include "drivers/camera/streaming_camera.hpp"

// Aravis' types, kept out of the header (glib would come with them).
typedef struct _ArvCamera ArvCamera;
typedef struct _ArvStream ArvStream;
typedef struct _ArvDevice ArvDevice;

namespace ccdlane {

class AravisCamera final : public StreamingCamera {
 public:
  // `id`: what arv_camera_new() takes: "Vendor-Model-Serial", a serial-bearing id, an IP
  // address (opened directly, no broadcast), or "Fake_1" (Aravis' in-process fake, whose
  // interface this enables).
  AravisCamera(std::string id, CameraSettings settings);
  ~AravisCamera() override;
  AravisCamera(const AravisCamera&) = delete;
  AravisCamera& operator=(const AravisCamera&) = delete;

  std::string open() override;
  void close() override;

  double max_frame_rate() const { return fps_max_; }  // at the current size, as the camera says
  int packet_size() const { return packet_size_; }    // GigE Vision; 0 otherwise
  // Sets any GenICam feature by name ("ExposureTime", "Gain", "BinningHorizontal"):
  // "" or one line saying why not. Remembered and applied again after a reopen.
  std::string set_control(const std::string& name, const std::string& value);

 private:
  bool bring_up() override;
  void on_stall() override;
  std::optional<CaptureStatus> wait_for_frame(const MutableImageView& into, FrameMeta& meta, std::int64_t now_ns,
                                              std::int64_t wake_ns) override;
  bool configure();
  bool set_feature(const char* name, const char* value);
  bool start_stream();
  void lose_camera(const char* why);
  void release_camera(bool camera_reachable);
  static void on_control_lost(ArvDevice* device, void* self);

  ArvCamera* camera_ = nullptr;
  ArvStream* stream_ = nullptr;
  std::atomic<bool> control_lost_{false};  // set from Aravis' heartbeat thread

  std::uint32_t arv_format_ = 0;
  double fps_max_ = 0;
  int packet_size_ = 0;
  std::size_t payload_ = 0;

  bool have_frame_id_ = false;
  std::uint64_t last_frame_id_ = 0;
};

}  // namespace ccdlane
