// The test pattern: stamped, moving, checked to the pixel; its source paces and ends;
// its processor tells intact from damaged frames.
#include "tests/support/test_pattern_source.hpp"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "base/clock.hpp"

namespace ccdlane {
namespace {

struct Frame {
  explicit Frame(int w, int h) : pixels(static_cast<std::size_t>(w * h)), view{pixels.data(), w, h, w} {}
  std::vector<std::uint8_t> pixels;
  MutableImageView view;
};

TEST(TestPattern, StampCarriesTheFrameNumberBeyond256AndTheCheckSeesEveryPixel) {
  Frame f(40, 30);
  render_test_pattern(f.view, 1'000'003);
  EXPECT_EQ(test_pattern_stamp(f.view), 1'000'003u);
  EXPECT_TRUE(test_pattern_intact(f.view, 1'000'003));
  EXPECT_FALSE(test_pattern_intact(f.view, 1'000'002));
  f.view.row(29)[39] ^= 1;  // the very last pixel
  EXPECT_FALSE(test_pattern_intact(f.view, 1'000'003));
}

TEST(TestPattern, ConsecutiveFramesDifferInEveryPixel) {
  Frame a(32, 8), b(32, 8);
  render_test_pattern(a.view, 5);
  render_test_pattern(b.view, 6);
  for (int y = 0; y < 8; ++y)
    for (int x = y == 0 ? 8 : 0; x < 32; ++x) ASSERT_NE(a.view.row(y)[x], b.view.row(y)[x]);
}

TEST(TestPatternSource, DeliversNumberedFramesThenEnds) {
  TestPatternOptions o;
  o.width = 16;
  o.height = 4;
  o.rate_hz = 0;  // unpaced
  o.frames = 3;
  TestPatternSource source(o);
  ASSERT_EQ(source.open(), "");
  Frame f(16, 4);
  FrameMeta meta;
  std::int64_t previous_t = 0;
  for (std::uint64_t n = 0; n < 3; ++n) {
    ASSERT_EQ(source.capture(f.view, meta, 100), CaptureStatus::frame);
    EXPECT_EQ(meta.sequence, n);
    EXPECT_GE(meta.t_ns, previous_t);
    previous_t = meta.t_ns;
    EXPECT_FALSE(meta.gyro.has_value());
    EXPECT_TRUE(test_pattern_intact(f.view, n));
  }
  EXPECT_EQ(source.capture(f.view, meta, 100), CaptureStatus::end_of_stream);
  EXPECT_EQ(source.counters().frames, 3u);
  EXPECT_EQ(source.describe(), "test-pattern 16x4 mono8 0 fps");
}

TEST(TestPatternSource, AFrameNotYetDueIsATimeout) {
  TestPatternOptions o;
  o.width = 16;
  o.height = 4;
  o.rate_hz = 1.0;  // the second frame is due a second after the first
  TestPatternSource source(o);
  ASSERT_EQ(source.open(), "");
  Frame f(16, 4);
  FrameMeta meta;
  EXPECT_EQ(source.capture(f.view, meta, 100), CaptureStatus::frame);
  const std::int64_t before = monotonic_ns();
  EXPECT_EQ(source.capture(f.view, meta, 20), CaptureStatus::timeout);
  EXPECT_GE(monotonic_ns() - before, 20'000'000) << "a timeout waits out its time";
}

TEST(TestPatternProcessor, IntactFramesAreOkDamagedOnesAreNot) {
  Frame f(16, 4);
  render_test_pattern(f.view, 9);
  FrameMeta meta;
  meta.sequence = 9;
  meta.t_ns = 123;
  TestPatternProcessor processor;
  const LaneEstimate good = processor.process(
      FrameInputs{4, meta.sequence, meta.frame_t_ns(), f.view, Gx1Angles{2.0, -1.5, 30.0}, AttitudeSource::live, {}});
  EXPECT_TRUE(good.ok);
  EXPECT_EQ(good.frame, 4u);  // the pipeline's count, not the source's id
  EXPECT_EQ(good.t_ns, 123);
  EXPECT_NEAR(good.phi_deg, 2.0, 1e-12);    // docs/gx1.md section 13: phi = roll
  EXPECT_NEAR(good.theta_deg, 1.5, 1e-12);  // theta = -pitch
  EXPECT_EQ(good.num_lines, 2);
  EXPECT_EQ(processor.damaged_frames(), 0u);

  meta.sequence = 10;  // the pixels say 9
  const LaneEstimate bad = processor.process(
      FrameInputs{5, meta.sequence, meta.frame_t_ns(), f.view, std::nullopt, AttitudeSource::none, {}});
  EXPECT_FALSE(bad.ok);
  EXPECT_EQ(bad.reason, EstimateFailure::no_frame);
  EXPECT_EQ(processor.damaged_frames(), 1u);
}

}  // namespace
}  // namespace ccdlane
