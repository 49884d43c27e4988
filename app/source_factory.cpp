// One row per source kind: adding a driver is one make_* function and one row.
#include "app/source_factory.hpp"

#include <stdexcept>

#include "app/synth_source.hpp"
#include "drivers/camera/camera_factory.hpp"
#include "drivers/frames/frame_directory.hpp"
#include "drivers/frames/frame_directory_source.hpp"

namespace ccdlane {
namespace {

std::unique_ptr<FrameSource> make_synth(const Config& c) {
  SynthSourceOptions o;
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
  return s;
}

std::unique_ptr<FrameSource> make_from_camera_factory(const std::string& source, const Config& c) {
  std::string error;
  auto camera = make_camera(source, camera_settings(c), error);
  if (!camera) throw std::runtime_error(error);
  return camera;
}

std::unique_ptr<FrameSource> make_v4l2(const Config& c) { return make_from_camera_factory("v4l2:" + c.source.device, c); }
std::unique_ptr<FrameSource> make_aravis(const Config& c) {
  return make_from_camera_factory("aravis:" + c.source.camera, c);
}

struct SourceKindRow {
  SourceKind kind;
  const char* name;
  std::unique_ptr<FrameSource> (*make)(const Config&);  // null: not in this build
};

constexpr SourceKindRow kSourceKinds[] = {
    {SourceKind::synth, "synth", make_synth},
    {SourceKind::frames, "frames", make_frames},
    {SourceKind::v4l2, "v4l2", make_v4l2},
    {SourceKind::aravis, "aravis", make_aravis},
};

const SourceKindRow* row_of(SourceKind kind) {
  for (const SourceKindRow& row : kSourceKinds)
    if (row.kind == kind) return &row;
  return nullptr;
}

}  // namespace

std::string frame_source_unavailable(const Config& config) {
  const SourceKindRow* row = row_of(config.source.kind);
  if (row && row->make) return "";
  return std::string("source.kind: \"") + (row ? row->name : "?") + "\" is not available in this build of ccdlaned";
}

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
    case SourceKind::aravis: break;
  }
  const SourceKindRow* row = row_of(config.source.kind);
  return std::string("source.kind: \"") + (row ? row->name : "?") + "\" frames carry no gyro reading";
}

std::unique_ptr<FrameSource> make_frame_source(const Config& config) {
  const SourceKindRow* row = row_of(config.source.kind);
  if (!row || !row->make) throw std::runtime_error(frame_source_unavailable(config));
  return row->make(config);
}

}  // namespace ccdlane
