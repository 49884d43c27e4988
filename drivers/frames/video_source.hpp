// A video file as the daemon's camera: frames delivered at the file's own rate (its
// timestamps), optionally looping, so that the service can be tried on a recorded drive.
#pragma once

#include <cstdio>
#include <memory>
#include <string>

#include "base/image_buffer.hpp"
#include "drivers/device_state.hpp"
#include "drivers/frame_source.hpp"
#include "drivers/frames/video_reader.hpp"

namespace ccdlane {

struct VideoSourceOptions {
  std::string path;   // the video file
  bool loop = false;  // start over at the end instead of reporting end_of_stream
  int width = 0;      // expected frame size (the camera's Nu x Nv); 0 = the video's
  int height = 0;
};

class VideoSource final : public FrameSource {
 public:
  explicit VideoSource(VideoSourceOptions options);
  ~VideoSource() override;

  // Opens the file; "" or one line naming the file and the cause (not a video, codec,
  // frame size against the camera's).
  std::string open() override;
  int width() const override { return reader_ ? reader_->width() : 0; }
  int height() const override { return reader_ ? reader_->height() : 0; }
  PixelFormat format() const override { return reader_ ? reader_->format() : PixelFormat::rgb8; }

  // Decodes the next frame ahead, sleeps until it is due (CLOCK_MONOTONIC, the first frame
  // at once), then copies it into `into`. meta.recorded_t_ns is its time in the file
  // (later passes of a loop shifted by one file length), meta.sequence counts frames since
  // open. Damage or a cut in the file: `error` once (counted, last_problem() names the
  // frame), then the end (or, looping, the start again).
  CaptureStatus capture(const MutableImageView& into, FrameMeta& meta, int timeout_ms) override;
  void close() override;
  std::string describe() const override;
  std::string last_problem() const override { return problem_.str(); }
  void copy_last_problem(char* out, std::size_t size) const override {
    if (size > 0) std::snprintf(out, size, "%s", problem_.c_str());
  }
  SourceCounters counters() const override { return counters_; }

 private:
  // Decodes the next frame into the staging buffer: frame, end_of_stream or error.
  CaptureStatus decode_ahead();

  VideoSourceOptions options_;
  std::unique_ptr<VideoReader> reader_;
  std::unique_ptr<ImageBuffer> staged_;  // the frame decoded ahead, waiting until due
  bool have_staged_ = false;
  std::int64_t staged_t_ns_ = 0;  // its time in the file
  std::int64_t anchor_ns_ = 0;    // monotonic time at which file time 0 of this pass is due
  bool started_ = false;
  std::int64_t pass_offset_ns_ = 0;  // added to file times on later passes of a loop
  std::int64_t last_t_ns_ = 0;       // the last frame's recorded time (for the next pass)
  std::int64_t period_ns_ = 33'333'333;
  std::uint64_t sequence_ = 0;
  SourceCounters counters_;
  ProblemText problem_;
};

}  // namespace ccdlane
