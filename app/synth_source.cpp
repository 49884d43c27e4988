// Rendering is far slower than a frame period (the renderer supersamples every mark
// edge), so it all happens before the daemon is ready and capture() is a paced memcpy.
#include "app/synth_source.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <thread>

#include "base/clock.hpp"
#include "core/synth/road_renderer.hpp"

namespace ccdlane {

int synth_source_frame_count(const Config& config) {
  const double most = std::floor(SynthSourceOptions::kMaxSeconds * config.synth.rate_hz);
  return std::max(1, static_cast<int>(std::min(static_cast<double>(config.synth.frames), most)));
}

SynthDrive synth_source_drive(const Config& config) {
  return SynthDrive(config.synth, config.nominal_pose(), synth_source_frame_count(config) / config.synth.rate_hz);
}

SynthSource::SynthSource(const Config& config, SynthSourceOptions options)
    : config_(config),
      options_(options),
      drive_(synth_source_drive(config)),
      width_(config.camera.Nu),
      height_(config.camera.Nv),
      count_(synth_source_frame_count(config)) {}

std::string SynthSource::open() {
  format_ = RoadRenderer(config_.camera, config_.synth).format();
  bits_ = format_ == PixelFormat::mono16 ? config_.synth.bits : 8;
  const std::ptrdiff_t stride = static_cast<std::ptrdiff_t>(width_) * bytes_per_pixel(format_);
  frame_bytes_ = static_cast<std::size_t>(stride) * static_cast<std::size_t>(height_);
  pixels_.assign(frame_bytes_ * static_cast<std::size_t>(count_), 0);
  gyro_.resize(static_cast<std::size_t>(count_));
  // Every core renders (the daemon waits for this before its first frame): thread t
  // renders frames t, t + T, ... with a renderer of its own (render() keeps state). The
  // calling thread asks `cancelled` and tells the others.
  const int threads = std::clamp(static_cast<int>(std::thread::hardware_concurrency()), 1, count_);
  std::atomic<bool> interrupted{false};
  const auto render_every = [&](int first) {
    RoadRenderer renderer(config_.camera, config_.synth);
    for (int k = first; k < count_; k += threads) {
      if (first == 0 && options_.cancelled && options_.cancelled()) interrupted.store(true, std::memory_order_relaxed);
      if (interrupted.load(std::memory_order_relaxed)) return;
      const SynthFrame truth = drive_.frame(static_cast<std::uint64_t>(k));
      renderer.render(truth, {pixels_.data() + frame_bytes_ * static_cast<std::size_t>(k), width_, height_, stride,
                              format_, bits_});
      gyro_[static_cast<std::size_t>(k)] = truth.gyro;
    }
  };
  std::vector<std::thread> helpers;
  for (int t = 1; t < threads; ++t) helpers.emplace_back(render_every, t);
  render_every(0);
  for (std::thread& h : helpers) h.join();
  if (interrupted.load()) return kSynthInterrupted;
  start_ns_ = monotonic_ns();
  next_ = 0;
  return "";
}

CaptureStatus SynthSource::capture(const MutableImageView& into, FrameMeta& meta, int timeout_ms) {
  if (options_.frames != 0 && next_ >= options_.frames) return CaptureStatus::end_of_stream;
  if (options_.rate_hz > 0.0) {
    const auto due =
        start_ns_ + static_cast<std::int64_t>(std::llround(static_cast<double>(next_) * 1e9 / options_.rate_hz));
    if (!sleep_until_due(due, timeout_ms)) return CaptureStatus::timeout;
  }
  const std::size_t k = static_cast<std::size_t>(next_ % static_cast<std::uint64_t>(count_));
  const std::uint8_t* src = pixels_.data() + frame_bytes_ * k;
  const std::size_t row_bytes = static_cast<std::size_t>(width_) * static_cast<std::size_t>(bytes_per_pixel(format_));
  for (int y = 0; y < height_; ++y) std::memcpy(into.row(y), src + row_bytes * static_cast<std::size_t>(y), row_bytes);
  meta.sequence = next_;
  meta.t_ns = monotonic_ns();
  meta.recorded_t_ns = drive_.t_ns(next_);  // the drive's clock, as `ccdlane synth` stamps frame n
  if (options_.gyro_in_meta)
    meta.gyro = gyro_[k];
  else
    meta.gyro.reset();
  ++next_;
  delivered_.fetch_add(1, std::memory_order_relaxed);
  return CaptureStatus::frame;
}

std::string SynthSource::describe() const {
  char text[128];
  std::snprintf(text, sizeof text, "synth %dx%d %s %.4g fps (%d frames of a %d-lane road, looping)", width_, height_,
                format_ == PixelFormat::mono16 ? "mono16" : "mono8", options_.rate_hz, count_, config_.synth.lanes);
  return text;
}

SourceCounters SynthSource::counters() const {
  SourceCounters c;
  c.frames = delivered_.load(std::memory_order_relaxed);
  return c;
}

}  // namespace ccdlane
