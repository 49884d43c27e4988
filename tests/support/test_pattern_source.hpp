// A moving test pattern stamped with its frame number: a FrameSource that needs no
// camera and a FrameProcessor that checks every pixel instead of finding lanes. They
// exercise the pipeline and the bus end to end (tests and benchmarks) and make a torn
// or misrouted frame visible.
#pragma once

#include <atomic>
#include <cstdint>
#include <string>

#include "daemon/frame_processor.hpp"
#include "drivers/frame_source.hpp"

namespace ccdlane {

// Frame n: pixel (x, y) = (x + 2y + 3n) mod 256, diagonal stripes moving right; the
// first 8 pixels of row 0 hold n (little-endian) so that n is known beyond 256 frames.
void render_test_pattern(const MutableImageView& into, std::uint64_t sequence);
// The frame number stamped in an image (mono8, at least 8 pixels wide).
std::uint64_t test_pattern_stamp(const ImageView& image);
// Every pixel is what render_test_pattern wrote for `sequence`.
bool test_pattern_intact(const ImageView& image, std::uint64_t sequence);

struct TestPatternOptions {
  int width = 800;
  int height = 600;
  double rate_hz = 30.0;     // 0: as fast as frames are asked for
  std::uint64_t frames = 0;  // then end of stream; 0: endless
};

class TestPatternSource : public FrameSource {
 public:
  explicit TestPatternSource(const TestPatternOptions& options);

  std::string open() override;
  int width() const override { return options_.width; }
  int height() const override { return options_.height; }
  PixelFormat format() const override { return PixelFormat::mono8; }
  // Paced on CLOCK_MONOTONIC: frame n is due at open time + n / rate_hz.
  CaptureStatus capture(const MutableImageView& into, FrameMeta& meta, int timeout_ms) override;
  void close() override {}
  std::string describe() const override;
  std::string last_problem() const override { return ""; }
  SourceCounters counters() const override;

 private:
  TestPatternOptions options_;
  std::int64_t start_ns_ = 0;
  std::uint64_t next_ = 0;
  std::atomic<std::uint64_t> delivered_{0};
};

// Stands in for the lane estimator: ok = true for an intact frame (two fixed lines
// 3.5 m apart, the gyro's roll and pitch mapped to the camera as phi and theta), ok =
// false with reason no_frame for a damaged one.
class TestPatternProcessor : public FrameProcessor {
 public:
  // `work_us`: busy time per frame, to play a slow estimator.
  explicit TestPatternProcessor(std::int64_t work_us = 0) : work_us_(work_us) {}

  LaneEstimate process(const FrameInputs& in) override;

  std::uint64_t damaged_frames() const { return damaged_.load(std::memory_order_relaxed); }
  void set_work_us(std::int64_t us) { work_us_.store(us, std::memory_order_relaxed); }

 private:
  std::atomic<std::int64_t> work_us_;
  std::atomic<std::uint64_t> damaged_{0};
};

}  // namespace ccdlane
