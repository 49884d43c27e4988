// The start-up memory estimate: 8192x8192 colour frames with queue_depth 62 (once a bare
// std::bad_alloc at start) need some 13 GB and are refused where that is more than half
// the machine; the default configuration needs a few MB.
#include "daemon/memory_estimate.hpp"

#include <string>

#include <gtest/gtest.h>

#include "app/config.hpp"
#include "app/synth_source.hpp"

namespace ccdlane {
namespace {

constexpr std::uint64_t kGiB = std::uint64_t{1} << 30;

Config huge_colour_camera() {
  Config c = default_config();
  c.source.kind = SourceKind::v4l2;
  c.source.pixel_format = SourcePixels::colour;
  c.camera.Nu = 8192;
  c.camera.Nv = 8192;
  c.daemon.queue_depth = 62;
  return c;
}

TEST(MemoryEstimate, TheFramePoolAtItsLargestPixel) {
  const Config c = huge_colour_camera();
  const std::uint64_t pixels = 8192ull * 8192ull;
  EXPECT_EQ(estimated_start_bytes(c), 64 * pixels * 3 + pixels * 8);
  Config grey = c;
  grey.source.pixel_format = SourcePixels::grey;  // may be 16-bit
  EXPECT_EQ(estimated_start_bytes(grey), 64 * pixels * 2 + pixels * 8);
}

// A synth source holds its rendered drive: [synth] frames, at most kMaxSeconds of them.
TEST(MemoryEstimate, TheSyntheticDriveAsTheSourceRendersIt) {
  Config c = default_config();
  c.source.kind = SourceKind::synth;
  const std::uint64_t pixels = static_cast<std::uint64_t>(c.camera.Nu) * static_cast<std::uint64_t>(c.camera.Nv);
  const std::uint64_t without_drive = (static_cast<std::uint64_t>(c.daemon.queue_depth) + 2) * pixels + pixels * 8;
  c.synth.frames = 50;
  EXPECT_EQ(estimated_start_bytes(c), without_drive + 50 * pixels);
  c.synth.frames = 100000;  // an hour at 30 Hz is not rendered: kMaxSeconds are
  EXPECT_EQ(estimated_start_bytes(c),
            without_drive + static_cast<std::uint64_t>(SynthSourceOptions::kMaxSeconds * c.synth.rate_hz) * pixels);
}

TEST(MemoryEstimate, MoreThanHalfTheMachineIsRefusedWithTheFigures) {
  const std::string why = memory_problem(huge_colour_camera(), 16 * kGiB);
  EXPECT_EQ(
      why.rfind("needs an estimated 12800 MB at start (daemon.queue_depth 62 + 2 frames of 8192x8192 at 3 bytes", 0),
      0u)
      << why;
  EXPECT_NE(why.find("more than half of the 16384 MB this machine has; lower queue_depth or the camera's size"),
            std::string::npos)
      << why;
  EXPECT_EQ(memory_problem(huge_colour_camera(), 64 * kGiB), "");
  EXPECT_EQ(memory_problem(default_config(), 1 * kGiB), "") << "the demo fits a small machine";
  EXPECT_GT(available_memory_bytes(), 0u);
}

}  // namespace
}  // namespace ccdlane
