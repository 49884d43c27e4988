// The pattern depends on every pixel's position and the frame number, so a frame that
// is torn (two frames mixed), stale (an older frame) or shifted fails the check.
#include "tests/support/test_pattern_source.hpp"

#include <cmath>
#include <cstdio>

#include "base/clock.hpp"
#include "core/geometry/gx1_attitude.hpp"
#include "core/geometry/types.hpp"

namespace ccdlane {
namespace {

std::uint8_t pattern_value(int x, int y, std::uint64_t n) {
  return static_cast<std::uint8_t>((static_cast<std::uint64_t>(x) + 2u * static_cast<std::uint64_t>(y) + 3u * n) &
                                   0xffu);
}

constexpr int kStampPixels = 8;

}  // namespace

void render_test_pattern(const MutableImageView& into, std::uint64_t sequence) {
  for (int y = 0; y < into.height; ++y) {
    std::uint8_t* row = into.row(y);
    for (int x = 0; x < into.width; ++x) row[x] = pattern_value(x, y, sequence);
  }
  for (int i = 0; i < kStampPixels && i < into.width; ++i)
    into.row(0)[i] = static_cast<std::uint8_t>((sequence >> (8 * i)) & 0xffu);
}

std::uint64_t test_pattern_stamp(const ImageView& image) {
  std::uint64_t n = 0;
  for (int i = 0; i < kStampPixels && i < image.width; ++i) n |= static_cast<std::uint64_t>(image.row(0)[i]) << (8 * i);
  return n;
}

bool test_pattern_intact(const ImageView& image, std::uint64_t sequence) {
  if (image.format != PixelFormat::mono8 || image.width < kStampPixels || image.height < 1) return false;
  if (test_pattern_stamp(image) != sequence) return false;
  for (int y = 0; y < image.height; ++y) {
    const std::uint8_t* row = image.row(y);
    for (int x = y == 0 ? kStampPixels : 0; x < image.width; ++x)
      if (row[x] != pattern_value(x, y, sequence)) return false;
  }
  return true;
}

TestPatternSource::TestPatternSource(const TestPatternOptions& options) : options_(options) {}

std::string TestPatternSource::open() {
  if (options_.width < kStampPixels || options_.height < 1) return "test pattern: frames must be at least 8x1 pixels";
  start_ns_ = monotonic_ns();
  next_ = 0;
  return "";
}

CaptureStatus TestPatternSource::capture(const MutableImageView& into, FrameMeta& meta, int timeout_ms) {
  if (options_.frames != 0 && next_ >= options_.frames) return CaptureStatus::end_of_stream;
  if (options_.rate_hz > 0.0) {
    const auto due =
        start_ns_ + static_cast<std::int64_t>(std::llround(static_cast<double>(next_) * 1e9 / options_.rate_hz));
    if (!sleep_until_due(due, timeout_ms)) return CaptureStatus::timeout;
  }
  render_test_pattern(into, next_);
  meta.sequence = next_;
  meta.t_ns = monotonic_ns();
  meta.gyro.reset();
  ++next_;
  delivered_.fetch_add(1, std::memory_order_relaxed);
  return CaptureStatus::frame;
}

std::string TestPatternSource::describe() const {
  char text[96];
  std::snprintf(text, sizeof text, "test-pattern %dx%d mono8 %.4g fps", options_.width, options_.height,
                options_.rate_hz);
  return text;
}

SourceCounters TestPatternSource::counters() const {
  SourceCounters c;
  c.frames = delivered_.load(std::memory_order_relaxed);
  return c;
}

LaneEstimate TestPatternProcessor::process(const FrameInputs& in) {
  const std::int64_t work_us = work_us_.load(std::memory_order_relaxed);
  if (work_us > 0) {  // busy, like an estimator, rather than sleeping
    const std::int64_t until = monotonic_ns() + work_us * 1000;
    while (monotonic_ns() < until) {
    }
  }
  LaneEstimate e;
  e.frame = in.frame;
  e.t_ns = in.t_ns;
  if (!in.image || !test_pattern_intact(*in.image, in.source_frame)) {
    damaged_.fetch_add(1, std::memory_order_relaxed);
    e.ok = false;
    e.reason = EstimateFailure::no_frame;
    return e;
  }
  e.ok = true;
  if (in.gyro) {
    const Attitude a = camera_attitude_from_gx1(*in.gyro);
    e.theta_deg = rad_to_deg(a.theta);
    e.phi_deg = rad_to_deg(a.phi);
  }
  e.num_lines = 2;
  e.lines[0] = EstimatedLine{0, 1750.0, 0.0, 0.0, 1, 1.0, kUndetermined};
  e.lines[1] = EstimatedLine{1, -1750.0, 0.0, 0.0, 1, 1.0, kUndetermined};
  e.lane_width_mm = 3500.0;
  e.lateral_offset_mm = 0.0;
  e.heading_deg = 0.0;
  e.departure = Departure::none;
  return e;
}

}  // namespace ccdlane
