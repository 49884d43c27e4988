// A frame directory as the daemon's camera: frames delivered at their recorded pace (or a
// fixed rate), optionally looping, with the recorded gyro reading of each frame.
#pragma once

#include <array>
#include <memory>
#include <string>

#include "drivers/frame_source.hpp"
#include "drivers/frames/frame_directory.hpp"

namespace ccdlane {

struct FrameDirectorySourceOptions {
  std::string path;      // the frame directory
  double rate_hz = 0.0;  // > 0: that many frames per second; 0: as recorded (t_ns)
  bool loop = false;     // start over at the end instead of reporting end_of_stream
  int width = 0;         // expected frame size (the camera's Nu x Nv); 0 = that of
  int height = 0;        //   the first readable frame
};

class FrameDirectorySource final : public FrameSource {
 public:
  explicit FrameDirectorySource(FrameDirectorySourceOptions options);
  ~FrameDirectorySource() override;

  std::string open() override;
  int width() const override { return width_; }
  int height() const override { return height_; }
  PixelFormat format() const override { return format_; }
  // Sample depth of the frames (8, or the bits of a 16-bit directory's maxval).
  int significant_bits() const { return significant_bits_; }

  // Sleeps until the frame is due (CLOCK_MONOTONIC), decodes it into `into`. meta.t_ns
  // is the monotonic delivery time, meta.recorded_t_ns the row's t_ns (later passes of a
  // loop: shifted by one recording length each); meta.sequence counts every frame
  // delivered or skipped, so it equals the frames.csv row during the first pass (as in
  // `ccdlane replay` of the directory). A damaged frame
  // returns `error` (counted; last_problem() names file and reason) and the next call
  // goes on with the next frame.
  CaptureStatus capture(const MutableImageView& into, FrameMeta& meta, int timeout_ms) override;
  void close() override;
  std::string describe() const override;
  std::string last_problem() const override;
  void copy_last_problem(char* out, std::size_t size) const override {
    if (size > 0) std::snprintf(out, size, "%s", problem_.data());
  }
  SourceCounters counters() const override { return counters_; }

  // The directory's index (valid after open()): rows, malformed-row issues, truth.
  const FrameDirectory* directory() const { return directory_.get(); }

 private:
  void set_problem(std::string_view text);

  FrameDirectorySourceOptions options_;
  std::unique_ptr<FrameDirectory> directory_;
  int width_ = 0, height_ = 0;
  PixelFormat format_ = PixelFormat::mono8;
  int significant_bits_ = 8;
  std::size_t next_ = 0;        // next row to deliver
  std::uint64_t pass_ = 0;      // completed passes over the directory (loop)
  std::int64_t anchor_ns_ = 0;  // monotonic time at which row 0 of this pass is due
  std::int64_t next_due_ns_ = 0;
  bool started_ = false;
  std::int64_t period_ns_ = 0;     // between passes when looping, and for rate_hz
  std::int64_t pass_span_ns_ = 0;  // recorded time from one pass's first frame to the next's
  SourceCounters counters_;
  std::array<char, 512> problem_{};
};

}  // namespace ccdlane
