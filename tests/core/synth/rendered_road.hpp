// Test fixtures around the synthetic road: a camera small enough for sanitizer builds,
// an LDW scenario's configuration, and a drive whose frames are rendered into one buffer on demand.
#pragma once

#include <vector>

#include "app/config.hpp"
#include "core/evaluation/ldw_scenarios.hpp"
#include "core/synth/road_renderer.hpp"
#include "core/synth/synth_drive.hpp"

namespace ccdlane::test {

// The reference camera at half resolution (400x300, same field of view and the same
// distortion at the same place in the picture), pitched 3 degrees down.
inline Config small_reference_camera() {
  Config c = default_config();
  c.camera.Nu = 400;
  c.camera.Nv = 300;
  c.camera.Uc_mm = c.camera.Vc_mm = 0.0084;
  c.camera.cx = 200.5;
  c.camera.cy = 150.5;
  c.camera.k_px2 = -8.3042e-7 * 4;
  c.attitude = {0.0, 3.0, 0.0};
  return c;
}

// The rendered-drive configuration of an LDW scenario: its road and vehicle, seen by the
// small camera, with the emulated gyro (the frames carry the gyro's roll: the lane
// filter does not track it).
inline Config scenario_config(const ldw::ScenarioSpec& spec) {
  Config c = small_reference_camera();
  c.detection.max_picks = 160;
  const VehicleScenario& d = spec.drive;
  c.synth.lanes = d.lanes;
  c.synth.ego_lane = d.ego_lane;
  c.synth.lane_width_mm = d.lane_width_m * 1e3;
  c.synth.line_width_mm = d.line_width_m * 1e3;
  c.synth.rate_hz = d.rate_hz;
  c.synth.seed = d.seed;
  c.vehicle = spec.vehicle;
  c.gyro.device = "emulated";
  return c;
}

// A drive over the configured road with a frame buffer of the camera's size.
struct RenderedRoad {
  Config config;
  SynthDrive drive;
  RoadRenderer renderer;
  std::vector<std::uint8_t> px;
  MutableImageView view;

  explicit RenderedRoad(const Config& c, PixelFormat format = PixelFormat::mono8, int bits = 8)
      : config(c),
        drive(c.synth, c.nominal_pose()),
        renderer(c.camera, c.synth),
        px(static_cast<std::size_t>(c.camera.Nu * c.camera.Nv * bytes_per_pixel(format))) {
    view = {px.data(), c.camera.Nu, c.camera.Nv, c.camera.Nu * bytes_per_pixel(format), format, bits};
  }
  // Renders frame k into the buffer and returns its truth.
  SynthFrame render(std::uint64_t k) {
    const SynthFrame f = drive.frame(k);
    renderer.render(f, view);
    return f;
  }
};

}  // namespace ccdlane::test
