// The factories: what each [source] kind and [gyro] device gives in this build, and a
// clear line for what it does not have.
#include <stdexcept>

#include <gtest/gtest.h>

#include "daemon/daemon.hpp"
#include "daemon/gyro_factory.hpp"
#include "daemon/processor_factory.hpp"
#include "daemon/source_factory.hpp"

namespace ccdlane {
namespace {

TEST(SourceFactory, SynthGivesFramesOfTheConfiguredCamera) {
  Config c = default_config();
  c.camera.Nu = 320;
  c.camera.Nv = 240;
  c.source.rate_hz = 25;
  EXPECT_EQ(frame_source_unavailable(c), "");
  auto source = make_frame_source(c);
  ASSERT_EQ(source->open(), "");
  EXPECT_EQ(source->width(), 320);
  EXPECT_EQ(source->height(), 240);
  EXPECT_EQ(source->format(), PixelFormat::mono8);
  EXPECT_EQ(source->describe(), "test-pattern 320x240 mono8 25 fps");
  EXPECT_NE(make_frame_processor(c, *source), nullptr);
}

TEST(SourceFactory, KindsThisBuildLacksAreOneClearLine) {
  Config c = default_config();
  for (const auto& [kind, name] : {std::pair{SourceKind::frames, "frames"}, std::pair{SourceKind::v4l2, "v4l2"},
                                   std::pair{SourceKind::aravis, "aravis"}}) {
    c.source.kind = kind;
    const std::string expected = std::string("source.kind: \"") + name + "\" is not available in this build of ccdlaned";
    EXPECT_EQ(frame_source_unavailable(c), expected);
    EXPECT_EQ(daemon_config_problem(c), expected);
    try {
      make_frame_source(c);
      ADD_FAILURE() << name;
    } catch (const std::runtime_error& e) {
      EXPECT_EQ(e.what(), expected);
    }
  }
}

TEST(GyroFactory, NoDeviceMeansNoGyroAndADeviceIsRefusedForNow) {
  Config c = default_config();
  EXPECT_EQ(attitude_provider_unavailable(c), "");
  EXPECT_EQ(make_attitude_provider(c), nullptr);
  c.gyro.device = "emulated";
  EXPECT_EQ(attitude_provider_unavailable(c),
            "gyro.device: \"emulated\": the 3DM-GX1 reader is not available in this build of ccdlaned");
  EXPECT_THROW(make_attitude_provider(c), std::runtime_error);
}

TEST(DemoConfig, IsRunnable) {
  const Config c = demo_config();
  EXPECT_EQ(daemon_config_problem(c), "");
  EXPECT_EQ(c.source.kind, SourceKind::synth);
  EXPECT_EQ(c.source.rate_hz, 30.0);
  EXPECT_EQ(c.lcm.url, "udpm://239.255.76.67:7667?ttl=0");
}

}  // namespace
}  // namespace ccdlane
