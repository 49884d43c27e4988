// [source] kind -> its driver: adding one is a make_* function and a case.
#include "app/source_factory.hpp"

#include <stdexcept>

#include "app/synth_source.hpp"
#include "drivers/camera/camera_factory.hpp"
#include "drivers/frames/frame_directory.hpp"
#include "drivers/frames/frame_directory_source.hpp"
#include "drivers/frames/video_source.hpp"

namespace ccdlane {
namespace {

std::unique_ptr<FrameSource> make_synth(const Config& c, std::function<bool()> cancelled) {
  SynthSourceOptions o;
  o.cancelled = std::move(cancelled);
  o.rate_hz = c.source.rate_hz;
  // With a gyro device (the emulator in the demo) the frames carry no reading of their
  // own, so that the live gyro is what the priors come from.
  o.gyro_in_meta = c.gyro.device.empty();
  return std::make_unique<SynthSource>(c, o);
}

std::unique_ptr<FrameSource> make_frames(const Config& c) {
  FrameDirectorySourceOptions o;
  o.path = c.source.path;
  o.rate_hz = c.source.rate_hz;
  o.loop = c.source.loop;
  o.width = c.camera.Nu;
  o.height = c.camera.Nv;
  return std::make_unique<FrameDirectorySource>(o);
}

// A recorded drive from a dashcam or a vehicle camera's file: played at its own rate.
std::unique_ptr<FrameSource> make_video(const Config& c) {
  VideoSourceOptions o;
  o.path = c.source.path;
  o.loop = c.source.loop;
  o.width = c.camera.Nu;
  o.height = c.camera.Nv;
  return std::make_unique<VideoSource>(o);
}

CameraSettings camera_settings(const Config& c) {
  CameraSettings s;
  s.width = c.camera.Nu;
  s.height = c.camera.Nv;
  s.fps = c.source.rate_hz;
  switch (c.source.pixel_format) {
    case SourcePixels::automatic: s.colour = ColourCapture::automatic; break;
    case SourcePixels::grey: s.colour = ColourCapture::grey; break;
    case SourcePixels::colour: s.colour = ColourCapture::colour; break;
  }
  s.device_format = c.source.device_format;
  return s;
}

std::unique_ptr<FrameSource> make_v4l2(const Config& c) {
  return make_camera("v4l2:" + c.source.device, camera_settings(c));
}
std::unique_ptr<FrameSource> make_aravis(const Config& c) {
  return make_camera("aravis:" + c.source.camera, camera_settings(c));
}

const char* kind_name(SourceKind kind) {
  switch (kind) {
    case SourceKind::synth: return "synth";
    case SourceKind::frames: return "frames";
    case SourceKind::v4l2: return "v4l2";
    case SourceKind::aravis: return "aravis";
    case SourceKind::video: return "video";
  }
  return "?";
}

}  // namespace

std::string frames_without_gyro(const Config& config) {
  switch (config.source.kind) {
    case SourceKind::synth: return "";
    case SourceKind::frames:
      try {
        const FrameDirectory directory(config.source.path);
        if (directory.has_gyro_columns()) return "";
        return "source.path: " + directory.csv_path() + " has no gyro columns (roll_deg, pitch_deg)";
      } catch (const FrameDirectoryError&) {
        return "";
      }
    case SourceKind::v4l2:
    case SourceKind::aravis:
    case SourceKind::video: break;
  }
  return std::string("source.kind: \"") + kind_name(config.source.kind) + "\" frames carry no gyro reading";
}

std::unique_ptr<FrameSource> make_frame_source(const Config& config, std::function<bool()> cancelled) {
  switch (config.source.kind) {
    case SourceKind::synth: return make_synth(config, std::move(cancelled));
    case SourceKind::frames: return make_frames(config);
    case SourceKind::v4l2: return make_v4l2(config);
    case SourceKind::aravis: return make_aravis(config);
    case SourceKind::video: return make_video(config);
  }
  throw std::logic_error("source.kind: not a kind the configuration loader accepts");  // a programmer's error
}

}  // namespace ccdlane
