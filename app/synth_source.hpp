// The built-in synthetic road as a camera: a few seconds of the [synth] drive rendered
// once at open(), then replayed paced at rate_hz and looping without a seam, so the demo
// needs no files and rendering costs nothing while the pipeline runs.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "app/config.hpp"
#include "core/synth/synth_drive.hpp"
#include "drivers/frame_source.hpp"

namespace ccdlane {

struct SynthSourceOptions {
  double rate_hz = 30.0;                      // playback pace; 0: as fast as frames are asked for
  bool gyro_in_meta = true;                   // put each frame's gyro reading in FrameMeta.gyro
  std::uint64_t frames = 0;                   // then end of stream; 0: loop for ever
  static constexpr double kMaxSeconds = 6.0;  // rendered ahead: at most this much drive
  // Asked between frames while open() renders: true gives up (open() returns
  // kSynthInterrupted), so that a stop request does not wait out seconds of rendering.
  std::function<bool()> cancelled;
};

// How many frames the source renders for `config`: [synth] frames, at most
// kMaxSeconds of the drive (memory: 800x600 mono8 is 0.5 MB a frame), at least 1.
int synth_source_frame_count(const Config& config);

// The drive a synth source for `config` plays: its rendered frames' span made to loop
// without a seam (SynthDrive's loop_s), so that frame n shows drive frame n mod count and
// the emulated gyro that follows it sees no jump at the loop either.
SynthDrive synth_source_drive(const Config& config);

// What SynthSource::open() returns when its `cancelled` said stop.
inline constexpr const char* kSynthInterrupted = "synth: start-up interrupted";

class SynthSource final : public FrameSource {
 public:
  SynthSource(const Config& config, SynthSourceOptions options);

  std::string open() override;  // renders every frame: about 10-50 ms each
  int width() const override { return width_; }
  int height() const override { return height_; }
  PixelFormat format() const override { return format_; }
  // Sleeps until frame n is due (open time + n / rate_hz) and copies rendered frame
  // n mod count into `into`; meta.sequence = n, meta.recorded_t_ns = n / [synth] rate_hz
  // (the drive's time, going on through the loops), meta.gyro = that frame's gyro reading.
  CaptureStatus capture(const MutableImageView& into, FrameMeta& meta, int timeout_ms) override;
  void close() override {}
  std::string describe() const override;
  std::string last_problem() const override { return ""; }
  SourceCounters counters() const override;

  // The truth of what frame n (capture's sequence) shows.
  SynthFrame truth(std::uint64_t n) const { return drive_.frame(n % static_cast<std::uint64_t>(count_)); }

 private:
  Config config_;
  SynthSourceOptions options_;
  SynthDrive drive_;
  int width_, height_, count_;
  PixelFormat format_ = PixelFormat::mono8;
  int bits_ = 8;
  std::size_t frame_bytes_ = 0;
  std::vector<std::uint8_t> pixels_;  // count_ frames, one after another
  std::vector<Gx1Angles> gyro_;
  std::int64_t start_ns_ = 0;
  std::uint64_t next_ = 0;
  std::atomic<std::uint64_t> delivered_{0};
};

}  // namespace ccdlane
