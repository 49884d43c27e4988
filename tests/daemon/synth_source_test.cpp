// The synth source renders its drive on every core at open(): each frame must be what one
// renderer on one thread makes of the drive's frame, with that frame's gyro reading
// (run under ThreadSanitizer too: the threads share the drive and write one buffer).
#include "app/synth_source.hpp"

#include <vector>

#include <gtest/gtest.h>

#include "core/synth/road_renderer.hpp"

namespace ccdlane {
namespace {

TEST(SynthSource, EveryCoreRendersWhatOneRendererWould) {
  Config c = default_config();
  c.synth.frames = 7;  // not a multiple of two or four threads
  c.synth.noise_sigma = 2.0;
  SynthSourceOptions o;
  o.rate_hz = 0.0;  // unpaced
  SynthSource source(c, o);
  ASSERT_EQ(source.open(), "");

  const SynthDrive drive = synth_source_drive(c);
  RoadRenderer renderer(c.camera, c.synth);
  const std::size_t bytes = static_cast<std::size_t>(c.camera.Nu) * static_cast<std::size_t>(c.camera.Nv);
  std::vector<std::uint8_t> got(bytes), want(bytes);
  for (std::uint64_t k = 0; k < 7; ++k) {
    FrameMeta meta;
    ASSERT_EQ(source.capture({got.data(), c.camera.Nu, c.camera.Nv, c.camera.Nu, PixelFormat::mono8, 8}, meta, 100),
              CaptureStatus::frame);
    const SynthFrame truth = drive.frame(k);
    renderer.render(truth, {want.data(), c.camera.Nu, c.camera.Nv, c.camera.Nu, PixelFormat::mono8, 8});
    EXPECT_EQ(got, want) << "frame " << k;
    ASSERT_TRUE(meta.gyro.has_value());
    EXPECT_EQ(meta.gyro->pitch_deg, truth.gyro.pitch_deg) << "frame " << k;
    EXPECT_EQ(source.truth(k).lateral_offset_mm, truth.lateral_offset_mm);
  }
}

// A stop asked for while it renders ends open() with kSynthInterrupted, whichever
// thread was rendering what.
TEST(SynthSource, AStopWhileRenderingEndsOpen) {
  Config c = default_config();
  c.synth.frames = 60;
  int asked = 0;
  SynthSourceOptions o;
  o.cancelled = [&asked] { return ++asked > 2; };
  SynthSource source(c, o);
  EXPECT_EQ(source.open(), kSynthInterrupted);
  EXPECT_EQ(asked, 3) << "the rendering stopped at the first yes";
}

}  // namespace
}  // namespace ccdlane
